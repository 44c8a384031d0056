#pragma once
#include <string>

namespace cdbench {

// Lower-case hex SHA-256 (OpenSSL's libcrypto) of a byte string, and of a file's content.
std::string sha256_hex(const std::string& bytes);
// Throws InputError naming the file when it cannot be read.
std::string sha256_file(const std::string& path);

}  // namespace cdbench
