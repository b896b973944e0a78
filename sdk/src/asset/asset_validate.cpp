// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Placeholder: being written.
#include "dermis/asset/asset_validate.h"
