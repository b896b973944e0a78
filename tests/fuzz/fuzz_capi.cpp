// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: what an engine does with a user's file through the C API: load from
// memory (the checksum rewritten, fuzz_checksum.h), create an instance with each deformer, destroy
// (docs/reliability.md).
#include <cstddef>
#include <cstdint>
#include <string>

#include "dermis/dermis.h"
#include "fuzz_checksum.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  dermis_character* c = nullptr;
  const std::string bytes = dermis::fuzz::WithChecksum(data, size);
  if (dermis_character_load_memory(bytes.data(), bytes.size(), "fuzz.dsurf", &c) != DERMIS_OK) {
    return 0;
  }
  for (dermis_deformer k : {DERMIS_DEFORMER_LBS, DERMIS_DEFORMER_DQS, DERMIS_DEFORMER_SWEEP}) {
    dermis_instance* inst = nullptr;
    if (dermis_instance_create(c, k, &inst) == DERMIS_OK) dermis_instance_destroy(inst);
  }
  dermis_character_destroy(c);
  return 0;
}
