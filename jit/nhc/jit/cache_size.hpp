#pragma once
/// \file cache_size.hpp
/// \brief The caches' size cap: the compile cache's libraries and the scene cache's entries
/// (cache.hpp, scene_cache.hpp) kept under one limit, the longest unused removed first.

#include <cstdint>
#include <filesystem>

namespace nhc::jit {

/// The size the cache's entries may take together: `$NHC_CACHE_MAX_SIZE` in bytes, or with a
/// suffix K, M or G (powers of 1024); 0 for no limit. 2 GiB when unset or unreadable.
std::uintmax_t cache_size_limit();

/// Marks an entry used now (its modification time): eviction removes the longest unused first.
void mark_used(const std::filesystem::path& entry) noexcept;

/// When the entries of the cache directory `directory` (its libraries with their digests, the
/// scene cache's entries in `scenes/`) take more than cache_size_limit(), removes them longest
/// unused first until they take at most 90 % of it, never `keep` (the entry just stored). A
/// removed entry is a miss for the next run, which rebuilds it.
void evict_over_limit(const std::filesystem::path& directory, const std::filesystem::path& keep) noexcept;

}  // namespace nhc::jit
