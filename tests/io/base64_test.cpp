// Base64 (geometry/io/base64.h): RFC 4648's test vectors, round trips of every length and byte, the size predicted
// before decoding, and each kind of malformed text refused with where it went wrong.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "geometry/io/base64.h"

namespace surfaced {
namespace {

std::string decoded_text(std::string_view text) {
    auto bytes = decode_base64(text);
    EXPECT_TRUE(bytes) << text << ": " << bytes.error().message;
    return bytes ? std::string(bytes->begin(), bytes->end()) : std::string();
}

TEST(Base64, Rfc4648Vectors) {
    const std::pair<std::string, std::string> vectors[] = {{"", ""},
                                                           {"f", "Zg=="},
                                                           {"fo", "Zm8="},
                                                           {"foo", "Zm9v"},
                                                           {"foob", "Zm9vYg=="},
                                                           {"fooba", "Zm9vYmE="},
                                                           {"foobar", "Zm9vYmFy"}};
    for (const auto& [plain, encoded] : vectors) {
        EXPECT_EQ(encode_base64(plain), encoded);
        EXPECT_EQ(decoded_text(encoded), plain);
        EXPECT_EQ(decoded_base64_size(encoded), plain.size()) << encoded;
    }
}

TEST(Base64, EveryLengthAndByteRoundTrips) {
    std::mt19937 rng(7);
    for (std::size_t n = 0; n < 100; ++n) {
        std::string bytes(n, '\0');
        for (char& c : bytes) c = static_cast<char>(rng() & 0xff);
        if (n == 99)
            for (std::size_t i = 0; i < 99; ++i) bytes[i] = static_cast<char>(i * 37 % 256);
        const std::string text = encode_base64(bytes);
        EXPECT_EQ(text.size() % 4, 0u);
        EXPECT_EQ(decoded_base64_size(text), n);
        EXPECT_EQ(decoded_text(text), bytes) << n;
    }
}

TEST(Base64, MalformedTextIsRefusedSayingWhere) {
    const std::pair<std::string, std::string> bad[] = {
        {"Zm9", "not padded"},               // length not a multiple of 4
        {"Zm9v*A==", "'*' at character 4"},  // outside the alphabet
        {"Zg=v", "'=' at character 2"},      // padding before the end
        {"Zh==", "stray bits"},              // 'h' leaves bits the padding drops
        {"Zm9=", "stray bits"},
        {"Zm 9", "byte 0x20 at character 2"},
    };
    for (const auto& [text, expected] : bad) {
        auto bytes = decode_base64(text);
        ASSERT_FALSE(bytes) << text;
        EXPECT_EQ(bytes.error().code, ErrorCode::ParseError);
        EXPECT_NE(bytes.error().message.find(expected), std::string::npos) << text << ": " << bytes.error().message;
    }
}

}  // namespace
}  // namespace surfaced
