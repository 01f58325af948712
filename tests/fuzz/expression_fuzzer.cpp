// libFuzzer target: arbitrary bytes as an expression over a small jet space. Every input must
// either parse or be rejected with nhc::ExpressionSyntaxError; the parsed expression must print
// and read back.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "nhc/expr/expression_printer.hpp"
#include "nhc/scene/expression_parser.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const nhc::JetSpace jet({"x", "y"}, 2, {"m", "g"});
  nhc::ExpressionRules rules;
  rules.allow_multipliers = true;
  const std::string text(reinterpret_cast<const char*>(data), size);
  GiNaC::ex e;
  try {
    e = nhc::parse_expression(text, jet, rules);
  } catch (const nhc::ExpressionSyntaxError&) {
    return 0;
  }
  // What we print, we must be able to read back (as nhc's own output: without the size limits
  // on scene input, which a printed product of powers or expansion may exceed).
  nhc::ExpressionRules own_output = rules;
  own_output.input_limits = false;
  try {
    nhc::parse_expression(nhc::to_text(e), jet, own_output);
  } catch (const nhc::ExpressionSyntaxError&) {
    std::abort();
  }
  return 0;
}
