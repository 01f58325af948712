#pragma once
/// \file scene_toml.hpp
/// \brief toml++ as scenes are read: with TOML 1.1's inline tables over several lines (a
/// [visual] entry, `wheel = { shape = "cylinder", …,\n rotation = "…" }`), which Debian's
/// compiled toml++ 3.3 leaves out. This header compiles the parser into the including file with
/// those features (header-only mode; toml++'s ABI namespaces keep it apart from the shared
/// library). Every reader of a scene file includes this instead of <toml++/toml.h>.

#ifdef TOML_HEADER_ONLY
#undef TOML_HEADER_ONLY
#endif
#define TOML_HEADER_ONLY 1
#ifdef TOML_SHARED_LIB
#undef TOML_SHARED_LIB
#endif
#define TOML_SHARED_LIB 0
#ifndef TOML_ENABLE_UNRELEASED_FEATURES
#define TOML_ENABLE_UNRELEASED_FEATURES 1
#endif
// toml++ 3.3's parser asserts, in a build without NDEBUG, and with NDEBUG under clang assumes
// (__builtin_assume: undefined behaviour when false) invariants that malformed input breaks: a
// table header "[#" reaches parse_key with '#' (found by the scene fuzzer). Debian's library,
// built with GCC and NDEBUG, compiles both away and the parser reports a syntax error; every
// build here does the same: NDEBUG is hidden from toml++ and its assertion is empty.
#pragma push_macro("NDEBUG")
#undef NDEBUG
#ifdef TOML_ASSERT
#undef TOML_ASSERT
#endif
#define TOML_ASSERT(expr) static_assert(true)
#include <toml++/toml.h>
#pragma pop_macro("NDEBUG")
