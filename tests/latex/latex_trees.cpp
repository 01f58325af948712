// Random expression trees printed by both printers, for latex_roundtrip_test.py --trees: the text
// form (to_text) one per line in TEXT, and the LaTeX as the documents print an equation
// (write_latex_equation: long ones broken into rows between terms and factors) in TEX.
//
//     nhc_latex_trees COUNT SEED TEXT TEX
//
// The trees are drawn with a fixed seed from a grammar meant to hit every bracketing decision:
// long sums (so that rows are broken), products with negative and fractional coefficients,
// nested powers, quotients of sums, negative and fractional exponents, function calls, and the
// names nhc prints specially (\dot{x}, \ddot{\theta}, \lambda_{1}, \mathrm{Jw}, q_{1}).
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/expr/expression_printer.hpp"
#include "nhc/expr/stable_symbol.hpp"

namespace {

using GiNaC::ex;

/// splitmix64: the same sequence on every platform (std:: distributions are not specified).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }
  bool chance(int percent) { return below(100) < percent; }

 private:
  std::uint64_t state_;
};

class Trees {
 public:
  explicit Trees(std::uint64_t seed) : random_(seed) {
    const std::vector<std::pair<std::string, std::string>> names = {{"a", ""},
                                                                    {"b", ""},
                                                                    {"m", ""},
                                                                    {"t", ""},
                                                                    {"x", ""},
                                                                    {"x_d1", "\\dot{x}"},
                                                                    {"th", "\\mathrm{th}"},
                                                                    {"th_d1", "\\dot{\\mathrm{th}}"},
                                                                    {"theta_d2", "\\ddot{\\theta}"},
                                                                    {"nu", "\\nu"},
                                                                    {"Jw", "\\mathrm{Jw}"},
                                                                    {"lambda1", "\\lambda_{1}"},
                                                                    {"lambda1_d1", "\\dot\\lambda_{1}"},
                                                                    {"q1", "q_{1}"},
                                                                    {"q1_d1", "\\dot{q}_{1}"}};
    for (const auto& [name, latex] : names) symbols_.push_back(nhc::stable_symbol(name, latex));
  }

  ex tree(int depth) {
    if (depth <= 0 || random_.chance(20)) return leaf();
    switch (random_.below(9)) {
      case 0:
      case 1:
        return sum(depth, 2 + random_.below(4));
      case 2:
      case 3:
        return product(depth);
      case 4:
        return power(depth);
      case 5:
        return tree(depth - 1) / sum(depth - 1, 2 + random_.below(3));  // quotient of sums
      case 6:
        return function(depth);
      case 7:
        return number() * sum(depth - 1, 2 + random_.below(3));
      default:
        return -tree(depth - 1);
    }
  }

  /// A long sum of product terms that contain sums and powers of sums: printed in several rows.
  ex long_sum() {
    GiNaC::exvector terms;
    const int n = 6 + random_.below(20);
    for (int k = 0; k < n; ++k) {
      ex term = number() * symbol() * GiNaC::pow(sum(2, 2 + random_.below(3)), 1 + random_.below(3));
      if (random_.chance(50)) term += GiNaC::pow(sum(2, 2), 2);
      if (random_.chance(30)) term *= sum(2, 2 + random_.below(4));
      terms.push_back(random_.chance(40) ? tree(4) : term);
    }
    return GiNaC::add(terms);
  }

 private:
  Random random_;
  std::vector<GiNaC::realsymbol> symbols_;

  ex symbol() { return symbols_[static_cast<std::size_t>(random_.below(static_cast<int>(symbols_.size())))]; }
  ex number() {
    static const std::vector<GiNaC::numeric> numbers = {1,
                                                        2,
                                                        3,
                                                        -1,
                                                        -2,
                                                        7,
                                                        GiNaC::numeric(1, 2),
                                                        GiNaC::numeric(-1, 2),
                                                        GiNaC::numeric(3, 4),
                                                        GiNaC::numeric(-5, 3),
                                                        GiNaC::numeric(22, 7)};
    return numbers[static_cast<std::size_t>(random_.below(static_cast<int>(numbers.size())))];
  }
  ex leaf() { return random_.chance(75) ? symbol() : number(); }
  ex sum(int depth, int n) {
    GiNaC::exvector terms;
    for (int k = 0; k < n; ++k) terms.push_back(tree(depth - 1));
    return GiNaC::add(terms);
  }
  ex product(int depth) {
    GiNaC::exvector factors;
    const int n = 2 + random_.below(3);
    for (int k = 0; k < n; ++k) factors.push_back(random_.chance(20) ? number() : tree(depth - 1));
    return GiNaC::mul(factors);
  }
  ex power(int depth) {
    static const std::vector<GiNaC::numeric> exponents = {
        2, 3, -1, -2, GiNaC::numeric(1, 2), GiNaC::numeric(-1, 2), GiNaC::numeric(3, 2), GiNaC::numeric(-3, 2)};
    const ex base = tree(depth - 1);
    if (random_.chance(15)) return GiNaC::pow(base, symbol());
    if (random_.chance(15)) return GiNaC::pow(GiNaC::pow(base, symbol()), exponents[random_.below(8)]);  // nested
    return GiNaC::pow(base, exponents[static_cast<std::size_t>(random_.below(static_cast<int>(exponents.size())))]);
  }
  ex function(int depth) {
    const ex arg = tree(depth - 1);
    switch (random_.below(6)) {
      case 0:
        return GiNaC::sin(arg);
      case 1:
        return GiNaC::cos(arg);
      case 2:
        return GiNaC::atan2(arg, tree(depth - 1));
      case 3:
        return GiNaC::tanh(arg);
      case 4:
        return GiNaC::abs(arg);
      default:
        return GiNaC::sqrt(arg);
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: nhc_latex_trees COUNT SEED TEXT TEX\n";
    return 2;
  }
  const int count = std::stoi(argv[1]);
  Trees trees(std::stoull(argv[2]));
  std::ofstream text(argv[3]), tex(argv[4]);
  for (int k = 0; k < count; ++k) {
    // One tree in three a long sum, the others of depth 2 to 5.
    ex e;
    for (;;) {
      // A drawn sum may cancel to 0: a tree that divides by it is drawn again, as is one where
      // GiNaC made a complex number (the square root of a negative one), outside nhc's scenes.
      try {
        e = k % 3 == 0 ? trees.long_sum() : trees.tree(2 + k % 4);
        if (!e.has(GiNaC::I)) break;
      } catch (const GiNaC::pole_error&) {
      }
    }
    text << nhc::to_text(e) << "\n";
    nhc::write_latex_equation(tex, "T_{" + std::to_string(k + 1) + "}", e);
  }
  if (!text || !tex) {
    std::cerr << "nhc_latex_trees: cannot write " << argv[3] << " or " << argv[4] << "\n";
    return 4;
  }
  return 0;
}
