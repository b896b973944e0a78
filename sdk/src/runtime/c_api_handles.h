// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The opaque handles of the C API (dermis/dermis.h) and its per-thread error message, shared
// with the C API of dermis::gpu (dermis/dermis_gpu.h). Internal.
#pragma once

#include <memory>
#include <string>

#include "dermis/dermis.h"
#include "dermis/runtime/runtime.h"

struct dermis_character {
  std::unique_ptr<dermis::RuntimeCharacter> impl;
};
struct dermis_output {
  std::unique_ptr<dermis::RuntimeOutput> impl;
};
struct dermis_instance {
  std::unique_ptr<dermis::RuntimeInstance> impl;
};

namespace dermis {
namespace c_api {

/// The calling thread's last error message (dermis_last_error()).
const char* LastError();
/// Sets the calling thread's dermis_last_error() and returns `status`.
dermis_status Fail(dermis_status status, const std::string& message);
/// DERMIS_OK for an ok status; otherwise Fail() with the matching code and the message.
dermis_status FromStatus(const Status& s);

}  // namespace c_api
}  // namespace dermis
