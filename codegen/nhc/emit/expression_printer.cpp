#include "nhc/emit/expression_printer.hpp"

#include <sstream>

namespace nhc {

std::string to_text(const GiNaC::ex& e) {
  std::ostringstream out;
  out << GiNaC::dflt << e;
  return out.str();
}

std::string to_latex(const GiNaC::ex& e) {
  std::ostringstream out;
  out << GiNaC::latex << e;
  return out.str();
}

}  // namespace nhc
