// Tests pipeline/io/sha256.cpp against the NIST FIPS 180-4 example vectors
// (csrc.nist.gov, "SHA256.pdf" examples) and the NIST CAVP "one million a" long message.
#include "pipeline/io/sha256.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace fogpipe::io {
namespace {

TEST(Sha256, HashesTheEmptyMessageToTheNistDigest) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256, HashesAbcToTheNistOneBlockDigest) {
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(Sha256, HashesTheNistTwoBlockMessage) {
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, HashesOneMillionAsInUnevenUpdates) {
  Sha256 sha;
  const std::string chunk(997, 'a');  // prime-sized updates cross every block boundary case
  std::size_t left = 1000000;
  while (left > 0) {
    const std::size_t n = std::min(left, chunk.size());
    sha.Update(chunk.data(), n);
    left -= n;
  }
  EXPECT_EQ(sha.FinishHex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, HashesAFileLikeTheSameBytesInMemory) {
  const std::string path = ::testing::TempDir() + "/fogpipe_sha256_test.bin";
  std::string bytes;
  for (int i = 0; i < 300000; ++i) bytes.push_back(static_cast<char>(i * 7 % 251));
  std::ofstream(path, std::ios::binary) << bytes;
  std::string error;
  const auto digest = Sha256FileHex(path, &error);
  ASSERT_TRUE(digest.has_value()) << error;
  EXPECT_EQ(*digest, Sha256Hex(bytes));
  std::remove(path.c_str());
  EXPECT_FALSE(Sha256FileHex(path, &error).has_value());
  EXPECT_NE(error.find(path), std::string::npos);
}

}  // namespace
}  // namespace fogpipe::io
