#pragma once
/// \file stable_symbol.hpp
/// \brief Symbols whose hash is the same in every build of nhc.
///
/// GiNaC orders the terms of sums and products by their hashes (basic::compare), and seeds a
/// symbol's hash with the address of its class's type name. For GiNaC::realsymbol that name is a
/// weak copy inside nhc's own executable (vague linkage: the dynamic linker resolves libginac's
/// references to it), so it moves whenever nhc is rebuilt; the term order followed, and with it
/// how fractions combine and the operation count of the generated code (the Whipple bicycle's
/// residual had 2,077, 2,094 and 2,128 operations after CSE in three builds of one generator).
/// Address randomization off (fixed_address_layout.hpp) made one binary repeat itself, not two
/// builds agree. A symbol made here carries a hash from its name alone; copies keep it.
///
/// From its name, not its serial number: serial numbers count every symbol the process made
/// before, so a hash from them ordered the same scene's terms differently when it was derived
/// after other scenes (the printed equations and the generated code followed). Symbols of one
/// scene have distinct names; two with one name (or a rare equal hash) are ordered by GiNaC by
/// serial, that is by their order of creation within the scene, which the scene alone decides.

#include <ginac/ginac.h>

#include <string>

namespace nhc {

/// The hash every nhc symbol named `name` gets (stable across builds and processes, whatever
/// was derived before).
unsigned stable_symbol_hash(const std::string& name);

/// A real symbol printed as `name` (LaTeX `latex`; GiNaC's default form of `name` when empty)
/// with a stable hash.
GiNaC::realsymbol stable_symbol(const std::string& name, const std::string& latex = "");

}  // namespace nhc
