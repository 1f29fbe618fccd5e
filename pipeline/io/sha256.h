// SHA-256 (FIPS 180-4, section 6.2), implemented here so that provenance needs no crypto library.
// Used to fingerprint input recordings and the effective configuration in every results file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace fogpipe::io {

/// Incremental SHA-256: Update() any number of times, then Finish() once.
class Sha256 {
 public:
  Sha256();
  void Update(const void* data, std::size_t size);
  void Update(const std::string& text) { Update(text.data(), text.size()); }
  /// The 32-byte digest. The object must not be updated afterwards.
  std::array<std::uint8_t, 32> Finish();
  /// Finish() as 64 lower-case hex characters.
  std::string FinishHex();

 private:
  void Compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffer_size_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// Hex SHA-256 of a string.
std::string Sha256Hex(const std::string& text);
/// Hex SHA-256 of a file's bytes, read in 1 MiB blocks (never the whole file at once).
/// Returns nullopt if the file cannot be read; *error says why.
std::optional<std::string> Sha256FileHex(const std::string& path, std::string* error);

}  // namespace fogpipe::io
