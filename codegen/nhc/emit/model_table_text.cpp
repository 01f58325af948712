// The C table as text (model_table_text.hpp).
#include "nhc/emit/model_table_text.hpp"

namespace nhc {

const char* model_table_text() noexcept {
  static const char* const text =
#include "nhc/emit/model_table_text.inc"
      ;
  return text;
}

}  // namespace nhc
