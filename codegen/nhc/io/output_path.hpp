#pragma once
/// \file output_path.hpp
/// \brief The one output policy (docs/safety.md): what a path given as an output may be, and
/// which file writing it replaces. Outputs never replace inputs: every command checks its output
/// paths against the files it reads, by device and inode, before it writes anything.
///
/// - a regular file (or a new name) is replaced atomically (atomic_file.hpp);
/// - a symbolic link is followed, and its final target is replaced atomically (the link stays);
/// - a character device (/dev/null, /dev/stdout) or a FIFO is written directly, never renamed
///   over; a FIFO without a reader is refused rather than waited on. The check opens it and holds
///   it open until the write, so a command refuses such an output before its work, and the reader
///   that was there at the check is the one that gets the bytes;
/// - a directory where a file is expected, a block device, a socket, and a path under an existing
///   file that is not a directory are refused (InputError, exit 2).

#include <string>
#include <vector>

namespace nhc {

/// Whether `a` and `b` name the same file: the same device and inode when both exist (hard and
/// symbolic links included), else the same canonical path.
bool same_file(const std::string& a, const std::string& b);

/// Where the bytes of an output named `path` go.
struct OutputTarget {
  enum class Kind { new_file, regular, stream };
  std::string path;            ///< `path` with its symbolic links followed (the file that is replaced)
  Kind kind = Kind::new_file;  ///< stream: a character device or FIFO, written in place
};

/// The policy above for `path`; throws InputError naming `path` when it may not be an output file.
OutputTarget output_target(const std::string& path);

/// Throws InputError (exit 2) naming both paths when `output` is the same file as one of `inputs`,
/// and when output_target() refuses it (a directory, a device other than a character device, …).
/// A character device or FIFO is opened here and held for take_held_output(); a FIFO nobody
/// reads is InputError now, not after the command's work.
void check_output_file(const std::string& output, const std::vector<std::string>& inputs);

/// The descriptor check_output_file() holds for the stream output `device` (an OutputTarget's
/// path of Kind::stream), handed over to the caller, who closes it; -1 when none is held.
int take_held_output(const std::string& device);

/// Opens the stream output `device` for writing without waiting for a reader, as
/// check_output_file() and a write without a check both do; `path` is the name the user gave.
/// Throws InputError for a FIFO without a reader, EnvironmentError for any other failure.
int open_stream_output(const std::string& path, const std::string& device);

/// As check_output_file() for an output directory: refused when it is one of `inputs` or an
/// existing file that is not a directory.
void check_output_directory(const std::string& output, const std::vector<std::string>& inputs);

}  // namespace nhc
