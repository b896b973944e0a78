// Placeholder: being written.
#include "dermis/plugins/assimp.h"
