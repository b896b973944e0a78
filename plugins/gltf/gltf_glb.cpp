// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The GLB container (glTF 2.0 specification, section "GLB File Format Specification") and
// base64, for the compression passes of the glTF plugin. Hand-written because tinygltf only
// reads and writes whole models (its base64 helpers are internal), and these are 80 lines.
#include "gltf_glb.h"

#include <cstdint>

namespace dermis::gltf_glb {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJson = 0x4E4F534A;
constexpr std::uint32_t kBin = 0x004E4942;
constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::uint32_t ReadU32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + std::size_t(i)]);
  return v;
}

void WriteU32(std::string* b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

}  // namespace

Status Split(const std::string& glb, std::string* json, std::string* bin) {
  json->clear();
  bin->clear();
  if (glb.size() < 20 || ReadU32(glb, 0) != kMagic || ReadU32(glb, 4) != 2 ||
      ReadU32(glb, 8) != glb.size() || ReadU32(glb, 16) != kJson) {
    return Status::InvalidInput("not a GLB version 2 file with a JSON chunk");
  }
  const std::size_t json_length = ReadU32(glb, 12);
  if (json_length > glb.size() - 20) return Status::InvalidInput("GLB JSON chunk overflows");
  *json = glb.substr(20, json_length);
  const std::size_t at = 20 + json_length;
  if (at + 8 <= glb.size() && ReadU32(glb, at + 4) == kBin) {
    const std::size_t bin_length = ReadU32(glb, at);
    if (bin_length > glb.size() - at - 8) return Status::InvalidInput("GLB BIN chunk overflows");
    *bin = glb.substr(at + 8, bin_length);
  }
  return Status::Ok();
}

std::string Join(const std::string& json, const std::string& bin) {
  std::string j = json, b = bin;
  while (j.size() % 4 != 0) j.push_back(' ');
  while (b.size() % 4 != 0) b.push_back('\0');
  const std::size_t total = 12 + 8 + j.size() + (b.empty() ? 0 : 8 + b.size());
  std::string out;
  out.reserve(total);
  WriteU32(&out, kMagic);
  WriteU32(&out, 2);
  WriteU32(&out, static_cast<std::uint32_t>(total));
  WriteU32(&out, static_cast<std::uint32_t>(j.size()));
  WriteU32(&out, kJson);
  out += j;
  if (!b.empty()) {
    WriteU32(&out, static_cast<std::uint32_t>(b.size()));
    WriteU32(&out, kBin);
    out += b;
  }
  return out;
}

std::string Base64(const std::string& bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size())
      v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 2]);
    out.push_back(kAlphabet[(v >> 18) & 63]);
    out.push_back(kAlphabet[(v >> 12) & 63]);
    out.push_back(i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=');
    out.push_back(i + 2 < bytes.size() ? kAlphabet[v & 63] : '=');
  }
  return out;
}

bool DecodeBase64(const std::string& text, std::string* bytes) {
  bytes->clear();
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : text) {
    if (c == '=') break;
    const char* at = nullptr;
    for (const char* p = kAlphabet; *p; ++p) {
      if (*p == c) at = p;
    }
    if (at == nullptr) return false;
    acc = (acc << 6) | static_cast<std::uint32_t>(at - kAlphabet);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes->push_back(static_cast<char>((acc >> bits) & 0xFFu));
    }
  }
  return true;
}

}  // namespace dermis::gltf_glb
