#pragma once
/// \file model_table_text.hpp
/// \brief The C table of docs/generated-code.md as text: runtime/nhc/runtime/model_table.h,
/// embedded at build time. Generated headers carry it verbatim (they stay self-contained), and
/// nhc::jit provides it to hand-written headers that `#include "nhc/runtime/model_table.h"`.

namespace nhc {

/// The complete text of nhc/runtime/model_table.h.
const char* model_table_text() noexcept;

/// The table's abi_version written by generated headers.
inline constexpr int kModelTableAbiVersion = 6;

}  // namespace nhc
