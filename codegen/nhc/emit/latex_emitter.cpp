#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/jet/expression_printer.hpp"
#include "nhc/jet/intermediate.hpp"

#include <string>
#include <vector>

namespace nhc {

namespace {

/// Scene names may contain '_', which is special in LaTeX text mode.
std::string latex_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '&' || c == '%' || c == '$' || c == '#' || c == '{' || c == '}')
      out += '\\';
    out += c;
  }
  return out;
}

/// Rows of LaTeX source per displayed row (about 100 rendered characters on the landscape page)
/// and rows per align* environment: TeX measures an environment as a whole, so a bicycle-sized
/// equation is split over many small ones (its width would otherwise exceed \maxdimen).
constexpr std::size_t kRowCharacters = 300;
constexpr int kRowsPerEnvironment = 40;

/// A term too long for one row as pieces that rows may be broken between: sums, products,
/// powers and function calls are opened up (with plain parentheses, which TeX lets a row break
/// leave unbalanced, unlike \\left( \\right)); subexpressions short enough stay one piece.
void append_pieces(const GiNaC::ex& e, std::vector<std::string>& out) {
  const std::string whole = to_latex(e);
  if (whole.size() <= kRowCharacters / 2) {
    out.push_back(whole);
    return;
  }
  if (GiNaC::is_a<GiNaC::add>(e)) {
    out.emplace_back("(");
    bool first = true;
    for (const GiNaC::ex& term : e) {
      std::vector<std::string> pieces;
      append_pieces(term, pieces);
      if (!first && !pieces.empty() && (pieces.front().empty() || pieces.front()[0] != '-'))
        pieces.front() = "+" + pieces.front();
      out.insert(out.end(), pieces.begin(), pieces.end());
      first = false;
    }
    out.emplace_back(")");
  } else if (GiNaC::is_a<GiNaC::mul>(e)) {
    GiNaC::numeric coefficient = 1;
    std::vector<GiNaC::ex> factors;
    for (const GiNaC::ex& f : e) {
      if (GiNaC::is_a<GiNaC::numeric>(f)) coefficient *= GiNaC::ex_to<GiNaC::numeric>(f);
      else factors.push_back(f);
    }
    if (coefficient.is_negative()) out.emplace_back("-"), coefficient = -coefficient;
    if (coefficient != 1) out.push_back(to_latex(coefficient));
    for (const GiNaC::ex& f : factors) append_pieces(f, out);
  } else if (GiNaC::is_a<GiNaC::power>(e)) {
    out.emplace_back("(");
    append_pieces(e.op(0), out);
    out.push_back(")^{" + to_latex(e.op(1)) + "}");
  } else if (GiNaC::is_a<GiNaC::function>(e)) {
    out.push_back("\\operatorname{" + GiNaC::ex_to<GiNaC::function>(e).get_name() + "}(");
    for (std::size_t k = 0; k < e.nops(); ++k) {
      if (k > 0) out.emplace_back(",");
      append_pieces(e.op(k), out);
    }
    out.emplace_back(")");
  } else {
    out.push_back(whole);
  }
}

/// Writes the rows of align* environments, opening a new environment every kRowsPerEnvironment.
class AlignWriter {
 public:
  explicit AlignWriter(std::ostream& out) : out_(out) { out_ << "\\begin{align*}\n"; }
  ~AlignWriter() { out_ << "\n\\end{align*}\n"; }
  AlignWriter(const AlignWriter&) = delete;
  AlignWriter& operator=(const AlignWriter&) = delete;

  void row(const std::string& text) {
    if (rows_ == kRowsPerEnvironment) {
      out_ << "\n\\end{align*}\n\\begin{align*}\n";
      rows_ = 0;
    }
    if (rows_ > 0) out_ << " \\\\\n";
    out_ << "  " << text;
    ++rows_;
  }

  /// `lhs &= e suffix`; a long sum is broken between its terms, continued rows indented.
  void equation(const std::string& lhs, const GiNaC::ex& e, const std::string& suffix) {
    const std::string whole = to_latex(e);
    if (whole.size() <= kRowCharacters) {
      row(lhs + " &= " + whole + suffix);
      return;
    }
    std::string current = lhs + " &= ";
    bool first_term = true;
    const GiNaC::ex terms = GiNaC::is_a<GiNaC::add>(e) ? e : GiNaC::ex(GiNaC::lst{e});
    for (const GiNaC::ex& term : terms) {
      std::vector<std::string> pieces;
      append_pieces(term, pieces);
      if (!first_term && !pieces.empty() && (pieces.front().empty() || pieces.front()[0] != '-'))
        pieces.front() = "+" + pieces.front();
      for (const std::string& piece : pieces) {
        if (current.size() > 8 && current.size() + piece.size() > kRowCharacters) {
          row(current);
          current = "&\\quad ";
        }
        current += piece + " ";
      }
      first_term = false;
    }
    row(current + suffix);
  }

 private:
  std::ostream& out_;
  int rows_ = 0;
};

}  // namespace

void write_derivation_latex(std::ostream& out, const Scene& scene,
                            const std::vector<DerivedModel>& models) {
  out << "\\documentclass[10pt]{article}\n"
         "\\usepackage[margin=2cm,landscape]{geometry}\n"
         "\\usepackage{amsmath}\n"
         "\\allowdisplaybreaks\n"
         "\\begin{document}\n"
      << "\\section*{Scene \\texttt{" << latex_text(scene.name) << "}}\n";
  {
    AlignWriter align(out);
    align.equation("L", scene.lagrangian, "");
    for (std::size_t a = 0; a < scene.constraints.size(); ++a)
      align.equation("f^{" + std::to_string(a + 1) + "}", scene.constraints[a], "");
  }
  for (const DerivedModel& model : models) {
    out << "\\subsection*{Model \\texttt{" << to_string(model.kind) << "}}\n";
    if (!model.applicable) {
      out << "Not applicable: " << latex_text(model.reason) << "\n";
      continue;
    }
    AlignWriter align(out);
    for (std::size_t i = 0; i < model.equations.size(); ++i)
      align.equation("R_{" + std::to_string(i + 1) + "}", model.equations[i], " = 0");
    for (std::size_t a = 0; a < model.constraints.size(); ++a)
      align.equation("f^{" + std::to_string(a + 1) + "}", model.constraints[a],
                     model.constraints_are_equations ? " = 0" : " = 0 \\quad\\text{(monitored)}");
  }
  const std::vector<GiNaC::ex> where = derivation_intermediates(scene, models);
  if (!where.empty()) {
    out << "\\subsection*{Where}\n"
           "Each quantity after the ones it uses; $\\partial_z X$ is the partial derivative of $X$ by "
           "$z$ and $\\dot X$ its time derivative (\\texttt{--format json} lists their expressions, "
           "\\texttt{nhc derive --expand} substitutes all).\n";
    AlignWriter align(out);
    for (const GiNaC::ex& d : where) {
      const auto& i = GiNaC::ex_to<Intermediate>(d);
      if (i.origin() == Intermediate::Origin::defined) align.equation(i.latex_name(), i.expression(), "");
    }
  }
  out << "\\end{document}\n";
}

}  // namespace nhc
