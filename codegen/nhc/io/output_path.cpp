#include "nhc/io/output_path.hpp"

#include <sys/stat.h>

#include <filesystem>

#include "nhc/errors.hpp"

namespace nhc {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}

namespace {

void refuse_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs)
    if (!input.empty() && same_file(output, input))
      throw InputError({output, 0, 0}, "the output " + output + " is the input " + input +
                                           " (the same file); writing it would destroy the input: choose "
                                           "another output path");
}

}  // namespace

void check_output_file(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  std::error_code ec;
  if (fs::is_directory(output, ec))
    throw InputError({output, 0, 0}, "the output " + output + " is a directory; a file name is expected");
}

void check_output_directory(const std::string& output, const std::vector<std::string>& inputs) {
  refuse_inputs(output, inputs);
  std::error_code ec;
  if (fs::exists(output, ec) && !fs::is_directory(output, ec))
    throw InputError({output, 0, 0}, "the output " + output + " exists and is not a directory");
}

}  // namespace nhc
