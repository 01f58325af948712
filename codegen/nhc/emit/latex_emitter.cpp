#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/expr/expression_printer.hpp"
#include "nhc/expr/intermediate.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace nhc {

namespace {

/// Scene names may contain '_', which is special in LaTeX text mode.
std::string latex_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '&' || c == '%' || c == '$' || c == '#' || c == '{' || c == '}') out += '\\';
    out += c;
  }
  return out;
}

/// Rows of LaTeX source per displayed row (about 100 rendered characters on the landscape page)
/// and rows per align* environment: TeX measures an environment as a whole, so a bicycle-sized
/// equation is split over many small ones (its width would otherwise exceed \maxdimen).
constexpr std::size_t kRowCharacters = 300;
constexpr int kRowsPerEnvironment = 40;
/// MathJax 2 refuses one formula larger than its buffer (TeX MAXBUFFER, 5 kB by default, which a
/// notebook's reader cannot be asked to raise): the math-only form closes its environments sooner.
constexpr int kRowsPerMathJaxEnvironment = 12;

/// e, standing at `position`, as pieces that rows may be broken between: a term too long for
/// one row has its sums, products, powers and function calls opened up (with plain parentheses,
/// which TeX lets a row break leave unbalanced, unlike \\left( \\right)); subexpressions short
/// enough stay one piece. Brackets follow the printer's one rule (needs_brackets): a piece is
/// bracketed exactly where to_latex would bracket it.
void append_pieces(const GiNaC::ex& e, Position position, std::vector<std::string>& out) {
  const std::string whole = to_latex(e, position);
  if (whole.size() <= kRowCharacters / 2) {
    out.push_back(whole);
    return;
  }
  const bool brackets = needs_brackets(e, position);
  if (GiNaC::is_a<GiNaC::add>(e)) {
    if (brackets) out.emplace_back("(");
    bool first = true;
    for (const GiNaC::ex& term : e) {
      std::vector<std::string> pieces;
      append_pieces(term, Position::term, pieces);
      if (!first && !pieces.empty() && (pieces.front().empty() || pieces.front()[0] != '-'))
        pieces.front() = "+" + pieces.front();
      out.insert(out.end(), pieces.begin(), pieces.end());
      first = false;
    }
    if (brackets) out.emplace_back(")");
  } else if (GiNaC::is_a<GiNaC::mul>(e)) {
    GiNaC::numeric coefficient = 1;
    std::vector<GiNaC::ex> factors;
    for (const GiNaC::ex& f : e) {
      if (GiNaC::is_a<GiNaC::numeric>(f)) coefficient *= GiNaC::ex_to<GiNaC::numeric>(f);
      else factors.push_back(f);
    }
    if (brackets) out.emplace_back("(");
    if (coefficient.is_negative()) out.emplace_back("-"), coefficient = -coefficient;
    if (coefficient != 1) out.push_back(to_latex(coefficient, Position::factor));
    for (const GiNaC::ex& f : factors) append_pieces(f, Position::factor, out);
    if (brackets) out.emplace_back(")");
  } else if (GiNaC::is_a<GiNaC::power>(e)) {
    if (brackets) out.emplace_back("(");
    out.emplace_back("(");
    append_pieces(e.op(0), Position::term, out);
    out.push_back(")^{" + to_latex(e.op(1)) + "}");
    if (brackets) out.emplace_back(")");
  } else if (GiNaC::is_a<GiNaC::function>(e)) {
    out.push_back("\\operatorname{" + GiNaC::ex_to<GiNaC::function>(e).get_name() + "}(");
    for (std::size_t k = 0; k < e.nops(); ++k) {
      if (k > 0) out.emplace_back(",");
      append_pieces(e.op(k), Position::term, out);
    }
    out.emplace_back(")");
  } else {
    out.push_back(whole);
  }
}

/// Writes the rows of align* environments, opening a new environment every kRowsPerEnvironment.
class AlignWriter {
 public:
  explicit AlignWriter(std::ostream& out, int rows_per_environment = kRowsPerEnvironment)
      : out_(out), rows_per_environment_(rows_per_environment) {
    out_ << "\\begin{align*}\n";
  }
  AlignWriter(std::ostream& out, const std::string& heading, int rows_per_environment)
      : AlignWriter(out, rows_per_environment) {
    if (!heading.empty()) row(heading);
  }
  ~AlignWriter() { out_ << "\n\\end{align*}\n"; }
  AlignWriter(const AlignWriter&) = delete;
  AlignWriter& operator=(const AlignWriter&) = delete;

  void row(const std::string& text) {
    if (rows_ == rows_per_environment_) {
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
      append_pieces(term, Position::term, pieces);
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
  int rows_per_environment_;
  int rows_ = 0;
};

/// The terms of the sum e that are linear in one of `symbols` gathered into one term per symbol:
/// (2 m_w + m_b) \ddot{x} on one row, not -2 m_w \ddot{x} and -m_b \ddot{x} apart. Only regroups
/// the terms as they stand (no expansion): linear in the number of terms.
GiNaC::ex gathered(const GiNaC::ex& e, const GiNaC::exset& symbols) {
  if (!GiNaC::is_a<GiNaC::add>(e) || symbols.empty()) return e;
  GiNaC::exvector rest;
  std::vector<std::pair<GiNaC::ex, GiNaC::exvector>> groups;  // symbol, its coefficients
  for (const GiNaC::ex& term : e) {
    std::optional<GiNaC::ex> key;
    bool several = false;
    if (symbols.count(term)) key = term;
    else if (GiNaC::is_a<GiNaC::mul>(term))
      for (const GiNaC::ex& factor : term)
        if (symbols.count(factor)) {
          several = key.has_value();
          key = factor;
        }
    if (!key || several) {
      rest.push_back(term);
      continue;
    }
    auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first.is_equal(*key); });
    if (group == groups.end()) group = groups.insert(groups.end(), {*key, {}});
    group->second.push_back(term / *key);
  }
  for (const auto& [symbol, coefficients] : groups) rest.push_back(GiNaC::add(coefficients) * symbol);
  return GiNaC::add(rest);
}

/// The symbols a residual is linear in and that readers gather by: the accelerations (order ≥ 2)
/// and the multipliers.
GiNaC::exset gathering_symbols(const JetSpace& jet, const GiNaC::ex& e) {
  GiNaC::exset symbols;
  for (const JetCoordinate& c : jet.jet_coordinates_in(e))
    if (c.kind == VariableKind::multiplier || c.order >= 2) symbols.insert(jet.symbol(c));
  return symbols;
}

/// Headings: sections in the document form, \text rows in the math-only form.
struct LatexForm {
  bool document = true;
  int rows() const { return document ? kRowsPerEnvironment : kRowsPerMathJaxEnvironment; }
  std::string heading(std::ostream& out, int level, const std::string& words, const std::string& name) const {
    if (document) {
      out << (level == 0 ? "\\section*{" : "\\subsection*{") << words << " \\texttt{" << latex_text(name) << "}}\n";
      return "";
    }
    return "&\\text{" + words + " }\\mathtt{" + latex_text(name) + "}";
  }
};

/// M_r u' = f_r entry by entry (docs/reduced-form.md), the dependent speeds it is evaluated
/// with, and the multipliers.
void write_reduced_latex(std::ostream& out, const JetSpace& jet, const ReducedForm& r, const LatexForm& form) {
  if (!r.available) {
    const std::string heading = form.heading(out, 1, "Multiplier-free form", "M_r u' = f_r");
    if (form.document) out << "Not available: " << latex_text(r.reason) << "\n";
    else AlignWriter(out, heading, form.rows()).row("&\\text{not available}");
    return;
  }
  std::string speeds;
  for (int i : r.independent) speeds += (speeds.empty() ? "" : ", ") + to_latex(jet.q(i, 1));
  AlignWriter align(out, form.heading(out, 1, "Multiplier-free form", "M_r u' = f_r"), form.rows());
  align.row("&M_r\\,\\dot u = f_r, \\quad u = (" + speeds + ")");
  for (std::size_t d = 0; d < r.dependent_speeds.size(); ++d)
    align.equation(to_latex(r.dependent_symbols[d]), r.dependent_speeds[d], "");
  auto speed = [&](unsigned k) { return to_latex(jet.q(r.independent[k], 0)); };
  for (unsigned i = 0; i < r.mass_matrix.rows(); ++i)
    for (unsigned j = 0; j < r.mass_matrix.cols(); ++j)
      align.equation("M_{{" + speed(i) + "}{" + speed(j) + "}}", r.mass_matrix(i, j), "");
  for (unsigned i = 0; i < r.forcing.size(); ++i) align.equation("f_{" + speed(i) + "}", r.forcing[i], "");
  for (std::size_t a = 0; a < r.multipliers.size(); ++a)
    align.equation(r.multiplier_names[a].back() == '\'' ? "\\dot\\lambda_{" + std::to_string(a + 1) + "}"
                                                        : "\\lambda_{" + std::to_string(a + 1) + "}",
                   r.multipliers[a], "");
}

void write_latex(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models,
                 const LatexForm& form) {
  const JetSpace& jet = *scene.jet;
  {
    AlignWriter align(out, form.heading(out, 0, "Scene", scene.name), form.rows());
    align.equation("L", scene.lagrangian, "");
    for (std::size_t a = 0; a < scene.constraints.size(); ++a)
      align.equation("f^{" + std::to_string(a + 1) + "}", scene.constraints[a], "");
  }
  for (const DerivedModel& model : models) {
    const std::string heading = form.heading(out, 1, "Model", to_string(model.kind));
    if (!model.applicable) {
      if (form.document) out << "Not applicable: " << latex_text(model.reason) << "\n";
      else AlignWriter(out, heading, form.rows()).row("&\\text{not applicable}");
      continue;
    }
    {
      AlignWriter align(out, heading, form.rows());
      // Named by their coordinate, as the text and JSON forms do: R_x, R_\psi.
      for (std::size_t i = 0; i < model.equations.size(); ++i)
        align.equation("R_{" + to_latex(jet.q(static_cast<int>(i), 0)) + "}",
                       gathered(model.equations[i], gathering_symbols(jet, model.equations[i])), " = 0");
      for (std::size_t a = 0; a < model.constraints.size(); ++a)
        align.equation("f^{" + std::to_string(a + 1) + "}", model.constraints[a],
                       model.constraints_are_equations ? " = 0" : " = 0 \\quad\\text{(monitored)}");
    }  // the block closes before the reduced form's heading
    if (model.reduced) write_reduced_latex(out, jet, *model.reduced, form);
  }
  const std::vector<GiNaC::ex> where = derivation_intermediates(scene, models);
  if (where.empty()) return;
  std::string heading;
  if (form.document)
    out << "\\subsection*{Where}\n"
           "Each quantity after the ones it uses (\\texttt{--format json} lists their expressions, "
           "\\texttt{nhc derive --expand} substitutes all).\n";
  else heading = "&\\text{where}";
  AlignWriter align(out, heading, form.rows());
  for (const GiNaC::ex& d : where) {
    const auto& i = GiNaC::ex_to<Intermediate>(d);
    if (i.origin() == Intermediate::Origin::defined) align.equation(i.latex_name(), i.expression(), "");
  }
}

}  // namespace

void write_derivation_latex(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models) {
  out << "\\documentclass[10pt]{article}\n"
         "\\usepackage[margin=2cm,landscape]{geometry}\n"
         "\\usepackage{amsmath}\n"
         "\\allowdisplaybreaks\n"
         "\\begin{document}\n";
  write_latex(out, scene, models, LatexForm{true});
  out << "\\end{document}\n";
}

void write_latex_equation(std::ostream& out, const std::string& lhs, const GiNaC::ex& e) {
  AlignWriter(out).equation(lhs, e, "");
}

void write_derivation_latex_math(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models) {
  write_latex(out, scene, models, LatexForm{false});
}

}  // namespace nhc
