// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Private to the SDK: explicit little-endian byte writing and bounds-checked reading shared by
// the binary formats (.dsurf, the asset stream, character files), and their FNV-1a checksum.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "dermis/core/status.h"

namespace dermis {

/// FNV-1a, 64 bit, over `bytes`.
inline std::uint64_t Fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

class ByteWriter {
 public:
  void U8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void U16(std::uint16_t v) { Bytes(v, 2); }
  void U32(std::uint32_t v) { Bytes(v, 4); }
  void I32(std::int32_t v) { Bytes(static_cast<std::uint32_t>(v), 4); }
  void U64(std::uint64_t v) { Bytes(v, 8); }
  void I64(std::int64_t v) { Bytes(static_cast<std::uint64_t>(v), 8); }
  void F64(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    Bytes(b, 8);
  }
  void F32(float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    Bytes(b, 4);
  }
  /// A length-prefixed (u64) byte string.
  void Str(std::string_view v) {
    U64(v.size());
    out_.append(v.data(), v.size());
  }
  std::string& str() { return out_; }

 private:
  void Bytes(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  std::string out_;
};

class ByteReader {
 public:
  ByteReader(std::string_view bytes, const std::string& name) : b_(bytes), name_(name) {}
  // Fails unless `count` items of `size` bytes remain.
  bool Need(std::uint64_t count, std::uint64_t size, const char* what) {
    if (!ok()) return false;
    const std::uint64_t left = b_.size() - pos_;
    if (size != 0 && count > left / size) {
      status_ = Status::InvalidInput(name_ + ": truncated or corrupt file: " + what + " needs " +
                                     std::to_string(count) + " x " + std::to_string(size) +
                                     " bytes at offset " + std::to_string(pos_) + ", " +
                                     std::to_string(left) + " left");
      return false;
    }
    return true;
  }
  std::uint64_t Raw(int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) {
      v |= static_cast<std::uint64_t>(
               static_cast<unsigned char>(b_[pos_ + static_cast<std::size_t>(i)]))
           << (8 * i);
    }
    pos_ += static_cast<std::size_t>(n);
    return v;
  }
  std::uint8_t U8(const char* what) {
    return Need(1, 1, what) ? static_cast<std::uint8_t>(Raw(1)) : 0;
  }
  std::uint16_t U16(const char* what) {
    return Need(1, 2, what) ? static_cast<std::uint16_t>(Raw(2)) : 0;
  }
  std::uint32_t U32(const char* what) {
    return Need(1, 4, what) ? static_cast<std::uint32_t>(Raw(4)) : 0;
  }
  std::int32_t I32(const char* what) { return static_cast<std::int32_t>(U32(what)); }
  std::uint64_t U64(const char* what) { return Need(1, 8, what) ? Raw(8) : 0; }
  std::int64_t I64(const char* what) { return static_cast<std::int64_t>(U64(what)); }
  double F64(const char* what) {
    const std::uint64_t b = U64(what);
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
  float F32(const char* what) {
    const std::uint32_t b = U32(what);
    float v;
    std::memcpy(&v, &b, 4);
    return v;
  }
  /// A length-prefixed (u64) byte string; empty after an error.
  std::string Str(const char* what) {
    const std::uint64_t n = U64(what);
    if (!Need(n, 1, what)) return {};
    std::string v(b_.substr(pos_, static_cast<std::size_t>(n)));
    pos_ += static_cast<std::size_t>(n);
    return v;
  }
  void Fail(const std::string& message) {
    if (ok()) status_ = Status::InvalidInput(name_ + ": " + message);
  }
  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  std::size_t pos() const { return pos_; }
  /// Bytes not read yet.
  std::size_t left() const { return b_.size() - pos_; }
  /// The name errors start with.
  const std::string& name() const { return name_; }

 private:
  std::string_view b_;
  std::string name_;
  std::size_t pos_ = 0;
  Status status_;
};

}  // namespace dermis
