#pragma once
/// \file sha256.hpp
/// \brief SHA-256 (OpenSSL's libcrypto) of text and of files: the compile cache's key and the
/// digest of each cached shared object, checked before it is loaded.

#include <filesystem>
#include <optional>
#include <string>

namespace nhc::tools {

/// The SHA-256 of `bytes`, 64 lowercase hexadecimal digits.
std::string sha256_hex(const std::string& bytes);

/// The SHA-256 of the file's bytes; nullopt when it cannot be read.
std::optional<std::string> sha256_file_hex(const std::filesystem::path& path);

}  // namespace nhc::tools
