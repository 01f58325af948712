#pragma once
/// \file output_path.hpp
/// \brief Outputs never replace inputs: every command checks its output paths against the files
/// it reads before it writes anything.

#include <string>
#include <vector>

namespace nhc {

/// Whether `a` and `b` name the same file: the same device and inode when both exist (hard and
/// symbolic links included), else the same canonical path.
bool same_file(const std::string& a, const std::string& b);

/// Throws InputError (exit 2) naming both paths when `output` is the same file as one of `inputs`,
/// and when `output` is an existing directory (a file is expected there).
void check_output_file(const std::string& output, const std::vector<std::string>& inputs);

/// As check_output_file() for an output directory: refused when it is one of `inputs` or an
/// existing file that is not a directory.
void check_output_directory(const std::string& output, const std::vector<std::string>& inputs);

}  // namespace nhc
