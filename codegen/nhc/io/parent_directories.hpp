#pragma once
/// \file parent_directories.hpp
/// \brief The one rule for an output whose directory does not exist yet, file or directory
/// alike (`-o results/run1.csv`, `-o reports/today`): its missing ancestors are created, and
/// removed again when the output is not written, so a failed command leaves nothing behind.

#include <string>
#include <vector>

namespace nhc {

/// Creates the missing ancestors of `path`, outermost first; returns them innermost first.
/// Throws EnvironmentError (and removes what it created) when one cannot be made.
std::vector<std::string> create_missing_parents(const std::string& path);

/// Throws EnvironmentError naming `path` unless it could be written by the rule above: its
/// nearest existing ancestor is a directory nhc may create entries in. Creates nothing; for a
/// command that checks its output before long work (an ensemble) and writes it later.
void check_can_create(const std::string& path);

/// Removes the directories create_missing_parents() made, innermost first, each only if empty.
void remove_created_parents(const std::vector<std::string>& created);

}  // namespace nhc
