// SHA-256 (FIPS 180-4) through OpenSSL's libcrypto (EVP interface): fingerprints input recordings
// and the effective configuration in every results file. docs/dependencies.md says why a library
// and not a hand-written hash.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

struct evp_md_ctx_st;  // OpenSSL's EVP_MD_CTX, kept out of this header

namespace fogpipe::io {

/// Incremental SHA-256: Update() any number of times, then Finish() once. Throws
/// std::runtime_error if libcrypto fails (it does not for SHA-256 short of running out of memory).
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(Sha256&&) noexcept;
  Sha256& operator=(Sha256&&) noexcept;
  void Update(const void* data, std::size_t size);
  void Update(const std::string& text) { Update(text.data(), text.size()); }
  /// The 32-byte digest. The object must not be updated afterwards.
  std::array<std::uint8_t, 32> Finish();
  /// Finish() as 64 lower-case hex characters.
  std::string FinishHex();

 private:
  struct FreeContext {
    void operator()(evp_md_ctx_st* context) const;
  };
  std::unique_ptr<evp_md_ctx_st, FreeContext> context_;
};

/// Hex SHA-256 of a string.
std::string Sha256Hex(const std::string& text);
/// Hex SHA-256 of a file's bytes, read in 1 MiB blocks (never the whole file at once).
/// Returns nullopt if the file cannot be read; *error says why.
std::optional<std::string> Sha256FileHex(const std::string& path, std::string* error);

}  // namespace fogpipe::io
