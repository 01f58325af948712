#include "nhc/expr/stable_symbol.hpp"

#include <cstdint>

#include "nhc/expr/expression_dag.hpp"

namespace nhc {

namespace {

/// Sets the hash on construction; sliced to realsymbol on return, the hash travels with the
/// copy (GiNaC copies `hashvalue` and the hash_calculated flag, and never recomputes a hash it has).
class StableSymbol : public GiNaC::realsymbol {
 public:
  explicit StableSymbol(const std::string& name) : GiNaC::realsymbol(name) { stabilize(); }
  StableSymbol(const std::string& name, const std::string& latex) : GiNaC::realsymbol(name, latex) { stabilize(); }

 private:
  void stabilize() {
    hashvalue = stable_symbol_hash(get_name());
    setflag(GiNaC::status_flags::hash_calculated);
  }
};

}  // namespace

unsigned stable_symbol_hash(const std::string& name) {
  std::uint64_t hash = 0x6e68632d73796d62;  // "nhc-symb"
  for (const unsigned char c : name) hash = mix_keys(hash, c);
  return static_cast<unsigned>(mix_keys(hash, name.size()));
}

GiNaC::realsymbol stable_symbol(const std::string& name, const std::string& latex) {
  if (latex.empty()) return StableSymbol(name);  // GiNaC's default LaTeX form of the name
  return StableSymbol(name, latex);
}

}  // namespace nhc
