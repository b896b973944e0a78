// Placeholder: being written.
#include "dermis/plugins/gltf.h"
