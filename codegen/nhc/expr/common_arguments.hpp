#pragma once
/// \file common_arguments.hpp
/// \brief Sharing common arguments of n-ary sums and products (after SymPy's `opt_cse`
/// `match_common_args`): a pair of operands that occurs together in several products, such as
/// b·a⁻¹ in each term of Appell–Hamel's R_x, R_y and D f, is computed once and used by all of
/// them; likewise a pair of terms in several sums, with signs normalized (a − b shared by
/// s = a − b + c and t = b − a + d, the latter as −(a − b)). Hash-consing (expression_dag.hpp)
/// finds equal subexpressions only where GiNaC's trees have them; this finds the ones inside
/// flat sums and products.
///
/// Greedy, as SymPy: repeatedly the pair found in the most sums or products is made one
/// instruction, while that saves an operation. Ties are broken by the instructions' structural
/// keys, so the result is the same in every run. Sums and products of more than
/// kLargestPairedArity operands take part only as they are (their pairs are not enumerated: the
/// count is quadratic in the arity).

#include <vector>

#include "nhc/expr/expression_dag.hpp"

namespace nhc {

inline constexpr int kLargestPairedArity = 48;

/// A DAG computing the same outputs with common pairs of operands shared; `outputs` (indices into
/// `dag`) are replaced by the corresponding indices of the result. Only what the outputs reach is
/// carried over.
ExpressionDag share_common_arguments(const ExpressionDag& dag, std::vector<int>& outputs);

}  // namespace nhc
