#pragma once
/// \file common_factors.hpp
/// \brief A factor common to several product terms of one sum taken out of them:
/// y₃·y₅·s + y₁·c·y₅ + … → y₅·(y₃·s + y₁·c) + …, k − 1 multiplications fewer for k terms. Only
/// products that nothing else uses are taken apart (a shared product stays computed once).
/// Greedy: the factor found in the most terms first (ties by structural key, so the result is
/// the same in every run), then again inside the new sum and among the terms left. Runs before
/// the common-argument pass (common_arguments.hpp), which shares pairs across instructions;
/// this pass works inside one sum.

#include <vector>

#include "nhc/expr/expression_dag.hpp"

namespace nhc {

/// A DAG computing the same outputs with common factors taken out of sums; `outputs` (indices
/// into `dag`) are replaced by the corresponding indices of the result. Only what the outputs
/// reach is carried over.
ExpressionDag factor_common_terms(const ExpressionDag& dag, std::vector<int>& outputs);

}  // namespace nhc
