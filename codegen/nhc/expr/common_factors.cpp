#include "nhc/expr/common_factors.hpp"

#include <algorithm>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "nhc/long_work.hpp"

namespace nhc {

namespace {

/// A term of a sum being factored: an instruction of the input DAG (`old`), or one already built
/// in the output (`built`), or a product of input instructions (`factors`, when it may be taken
/// apart).
struct Term {
  int old = -1;
  int built = -1;
  bool negated = false;
  std::vector<int> factors;
};

class CommonFactors {
 public:
  CommonFactors(const ExpressionDag& dag, const std::vector<int>& outputs) : dag_(dag) {
    for (int id : dag.reachable(outputs))
      for (int a : dag[id].args) ++uses_[a];
    for (int o : outputs) uses_[o] += 2;
    built_.assign(static_cast<std::size_t>(dag.size()), -1);
  }

  ExpressionDag rebuild(std::vector<int>& outputs) {
    for (int id : dag_.reachable(outputs)) {
      check_for_stop();  // the stop question of long work (nhc/long_work.hpp)
      build(id);
    }
    for (int& o : outputs) o = built_[static_cast<std::size_t>(o)];
    return std::move(out_);
  }

 private:
  /// Instructions are built in increasing order, so operands are built first.
  int build(int id) {
    int& slot = built_[static_cast<std::size_t>(id)];
    if (slot >= 0) return slot;
    const Instruction& in = dag_[id];
    if (in.op == OpCode::sum) {
      std::vector<Term> terms;
      for (std::size_t k = 0; k < in.args.size(); ++k) {
        Term t;
        t.old = in.args[k];
        t.negated = in.negated[k];
        const Instruction& a = dag_[t.old];
        if (a.op == OpCode::product && uses_[t.old] == 1) t.factors = a.args;
        terms.push_back(std::move(t));
      }
      slot = factor_sum(std::move(terms));
      return slot;
    }
    Instruction copy = in;
    for (int& a : copy.args) a = built_[static_cast<std::size_t>(a)];
    slot = out_.append(std::move(copy));
    return slot;
  }

  int built_of(const Term& t) {
    if (t.built >= 0) return t.built;
    if (t.factors.empty()) return built_[static_cast<std::size_t>(t.old)];
    if (t.factors.size() == 1) return built_[static_cast<std::size_t>(t.factors[0])];
    Instruction p;
    p.op = OpCode::product;
    for (int f : t.factors) p.args.push_back(built_[static_cast<std::size_t>(f)]);
    return out_.append(std::move(p));
  }

  int factor_sum(std::vector<Term> terms) {
    for (;;) {
      // The factor in the most product terms (each term counted once).
      std::unordered_map<int, int> count;
      for (const Term& t : terms) {
        std::vector<int> distinct = t.factors;
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        for (int f : distinct) ++count[f];
      }
      int best = -1, best_count = 1;
      for (const auto& [f, c] : count)
        if (c > best_count ||
            (c == best_count && best >= 0 && std::make_pair(dag_[f].key, f) < std::make_pair(dag_[best].key, best))) {
          if (c < 2) continue;
          best = f;
          best_count = c;
        }
      if (best < 0) break;
      std::vector<Term> inner, rest;
      for (Term& t : terms) {
        const auto at = std::find(t.factors.begin(), t.factors.end(), best);
        if (at == t.factors.end()) {
          rest.push_back(std::move(t));
          continue;
        }
        t.factors.erase(at);
        if (t.factors.size() == 1) {  // the one factor left is a plain term
          t.old = t.factors[0];
          t.factors.clear();
        }
        inner.push_back(std::move(t));
      }
      Instruction p;
      p.op = OpCode::product;
      p.args = {built_[static_cast<std::size_t>(best)], factor_sum(std::move(inner))};
      Term factored;
      factored.built = out_.append(std::move(p));
      rest.push_back(std::move(factored));
      terms = std::move(rest);
    }
    if (terms.size() == 1 && !terms[0].negated) return built_of(terms[0]);
    Instruction s;
    s.op = OpCode::sum;
    for (const Term& t : terms) {
      s.args.push_back(built_of(t));
      s.negated.push_back(t.negated);
    }
    return out_.append(std::move(s));
  }

  const ExpressionDag& dag_;
  ExpressionDag out_{{}};
  std::unordered_map<int, int> uses_;
  std::vector<int> built_;
};

}  // namespace

ExpressionDag factor_common_terms(const ExpressionDag& dag, std::vector<int>& outputs) {
  CommonFactors pass(dag, outputs);
  return pass.rebuild(outputs);
}

}  // namespace nhc
