#pragma once
/// \file numeric_program.hpp
/// \brief Expressions lowered once into one shared instruction list (the common-subexpression
/// DAG the code generator prints, nhc/expr/expression_dag.hpp) and evaluated in doubles by walking it.
///
/// The linearizer evaluates the reduced residual, hidden constraints and their Jacobians at many
/// points (a sweep, its bisections, the chord iterations of steady_families). GiNaC's
/// substitution re-walks every expression tree each time, which for the Whipple bicycle (a
/// 1.4 MB derivation) costs seconds per point; the lowered list, with each shared
/// subexpression computed once, costs milliseconds. The consistent initialization's Newton
/// iterations evaluate through it too (consistent_initialization.cpp).

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/expr/evaluation_program.hpp"
#include "nhc/expr/expression_dag.hpp"

namespace nhc {

class NumericProgram {
 public:
  /// `inputs`: the symbols the expressions may contain, in the order evaluate() takes values.
  explicit NumericProgram(const std::vector<GiNaC::ex>& inputs);

  /// Adds an output; returns its index in evaluate()'s result. Throws MathError for a symbol
  /// that is not an input or a function without a double counterpart. `label` names the output
  /// in evaluate()'s errors ("" for its number).
  int add(const GiNaC::ex& e, std::string label = "");

  /// The outputs at `values` (one per input). Throws MathError naming the output's label (else
  /// `what` and its number) when one is not finite.
  std::vector<double> evaluate(const std::vector<double>& values, const std::string& what) const;
  /// The outputs at `values` as they come: inf and NaN where an output is not finite there.
  std::vector<double> values_at(const std::vector<double>& values) const;

  /// Lowers the outputs now (evaluate() does it on its first call): the program's last GiNaC
  /// work, done before a run that evaluates it without the symbolic lock (nhc/long_work.hpp).
  void prepare() const;

 private:
  ExpressionDag dag_;
  std::vector<int> outputs_;
  std::vector<std::string> labels_;
  mutable EvaluationProgram program_;  ///< the outputs' instructions, lowered on first use
  mutable bool prepared_ = false;
};

}  // namespace nhc
