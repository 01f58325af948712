#include "nhc/expr/common_arguments.hpp"

#include <algorithm>
#include <cstdint>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "nhc/long_work.hpp"

namespace nhc {

namespace {

/// One operand of a sum or product: an instruction of the input DAG (index < N) or a shared pair
/// made by this pass (index ≥ N); `negated` only in sums. A quotient n / d takes part as the
/// product of n's factors and d⁻¹ (as SymPy's Mul holds Pow(d, −1)), so that y·p/w common to
/// several quotients is found: d⁻¹ is the operand ~d (negative), `inverse`.
struct Operand {
  int node = 0;
  bool negated = false;
  int id() const { return inverse ? ~node : node; }
  bool inverse = false;
};

/// A sum or product of the input DAG whose operands the pass may rewrite.
struct Site {
  int instruction = 0;
  bool sum = false;
  std::vector<Operand> operands;
};

/// (sum?, first, second, opposite): first + second or first − second (sums), first · second
/// (products; one of them may be an inverse ~d, the pair then being a quotient), first and second
/// ordered by their structural keys.
using PairId = std::tuple<bool, int, int, bool>;

struct PairIdHash {
  std::size_t operator()(const PairId& p) const {
    const auto [sum, first, second, opposite] = p;
    return static_cast<std::size_t>(
        mix_keys(mix_keys(static_cast<std::uint64_t>(first) * 4 + (sum ? 2 : 0) + (opposite ? 1 : 0),
                          static_cast<std::uint64_t>(second)),
                 0));
  }
};

/// The sites a pair occurs in, increasing (a sorted vector: most pairs occur in few sites).
using Sites = std::vector<int>;

struct Pair {
  PairId id;
  std::uint64_t key = 0;
  int definition_site = -1;  ///< a site that computes exactly this pair, if any
};

class CommonArguments {
 public:
  CommonArguments(const ExpressionDag& dag, const std::vector<int>& outputs) : dag_(dag) {
    const std::vector<int> reached = dag.reachable(outputs);
    // A quotient's numerator that is a product used by nothing else is taken apart into the
    // quotient's site (absorbed: no site of its own, and not rebuilt).
    std::unordered_map<int, int> uses;
    for (int id : reached)
      for (int a : dag[id].args) ++uses[a];
    for (int o : outputs) uses[o] += 2;
    std::unordered_map<int, bool> absorbed;
    for (int id : reached) {
      const Instruction& in = dag[id];
      if (in.op == OpCode::quotient && dag[in.args[0]].op == OpCode::product && uses[in.args[0]] == 1)
        absorbed[in.args[0]] = true;
    }
    for (int id : reached) {
      const Instruction& in = dag[id];
      if (in.op == OpCode::quotient) {
        Site site{id, false, {}};
        if (absorbed.count(in.args[0]))
          for (int a : dag[in.args[0]].args) site.operands.push_back({a, false, false});
        else site.operands.push_back({in.args[0], false, false});
        site.operands.push_back({in.args[1], false, true});
        site_of_.emplace(id, static_cast<int>(sites_.size()));
        sites_.push_back(std::move(site));
        continue;
      }
      if (in.op != OpCode::sum && in.op != OpCode::product) continue;
      if (absorbed.count(id)) continue;
      Site site{id, in.op == OpCode::sum, {}};
      for (std::size_t k = 0; k < in.args.size(); ++k)
        site.operands.push_back({in.args[k], in.op == OpCode::sum && in.negated[k], false});
      site_of_.emplace(id, static_cast<int>(sites_.size()));
      sites_.push_back(std::move(site));
    }
    for (int s = 0; s < static_cast<int>(sites_.size()); ++s) {
      check_for_stop();  // the stop question of long work (nhc/long_work.hpp)
      if (static_cast<int>(sites_[static_cast<std::size_t>(s)].operands.size()) <= kLargestPairedArity)
        for_each_pair(s, [&](const PairId& p) { enter(p, s); });
    }
  }

  void share() {
    while (!queue_.empty()) {
      check_for_stop();  // the stop question of long work (nhc/long_work.hpp)
      const auto [count, tie, id] = queue_.top();
      queue_.pop();
      const auto found = sites_with_.find(id);
      if (found == sites_with_.end()) continue;
      const int now = static_cast<int>(found->second.size());
      if (now != count) {  // stale: its count changed since
        if (now >= 2) queue_.emplace(now, tie, id);
        continue;
      }
      apply(id);
    }
  }

  ExpressionDag rebuild(std::vector<int>& outputs) {
    ExpressionDag out{{}};
    const int n = dag_.size();
    built_.assign(static_cast<std::size_t>(n) + pairs_.size(), -1);
    for (int id : dag_.reachable(outputs)) build(out, id);
    for (int& o : outputs) o = built_[static_cast<std::size_t>(o)];
    return out;
  }

 private:
  std::uint64_t key_of(int node) const {
    if (node < 0) return mix_keys(key_of(~node), 0x696e7665727365ULL);  // an inverse ~d
    return node < dag_.size() ? dag_[node].key : pairs_[static_cast<std::size_t>(node - dag_.size())].key;
  }

  /// The canonical pair of two operands of one site.
  PairId pair_of(bool sum, const Operand& a, const Operand& b) const {
    const bool a_first = std::make_pair(key_of(a.id()), a.id()) < std::make_pair(key_of(b.id()), b.id());
    const Operand& first = a_first ? a : b;
    const Operand& second = a_first ? b : a;
    return {sum, first.id(), second.id(), sum && first.negated != second.negated};
  }

  template <class F>
  void for_each_pair(int s, F&& f) const {
    const Site& site = sites_[static_cast<std::size_t>(s)];
    for (std::size_t i = 0; i < site.operands.size(); ++i)
      for (std::size_t j = i + 1; j < site.operands.size(); ++j)
        if (site.operands[i].node != site.operands[j].node && !(site.operands[i].inverse && site.operands[j].inverse))
          f(pair_of(site.sum, site.operands[i], site.operands[j]));
  }

  static std::uint64_t tie_of(const PairId& p, std::uint64_t first_key, std::uint64_t second_key) {
    return mix_keys(mix_keys(mix_keys(std::get<0>(p) ? 2 : 1, first_key), second_key), std::get<3>(p) ? 2 : 1);
  }

  void enter(const PairId& p, int s) {
    Sites& sites = sites_with_[p];
    const auto at = std::lower_bound(sites.begin(), sites.end(), s);
    if (at == sites.end() || *at != s) sites.insert(at, s);
    if (sites.size() >= 2)
      queue_.emplace(static_cast<int>(sites.size()), tie_of(p, key_of(std::get<1>(p)), key_of(std::get<2>(p))), p);
  }

  void leave(const PairId& p, int s) {
    const auto it = sites_with_.find(p);
    if (it == sites_with_.end()) return;
    Sites& sites = it->second;
    const auto at = std::lower_bound(sites.begin(), sites.end(), s);
    if (at != sites.end() && *at == s) sites.erase(at);
    if (sites.empty()) sites_with_.erase(it);
  }

  /// Makes p one instruction used by every site that has it, when that saves an operation: each
  /// larger site saves one; the pair costs one unless a site computes exactly it.
  void apply(const PairId& p) {
    const Sites sites = sites_with_.at(p);
    const auto [sum, first, second, opposite] = p;
    // A site of exactly the two operands computes the pair (or, a sum whose first operand is
    // subtracted, its negative: left as it is).
    std::vector<int> exact, larger;
    for (int s : sites) {
      const Site& site = sites_[static_cast<std::size_t>(s)];
      if (site.operands.size() > 2) larger.push_back(s);
      else if (!(site.operands[0].id() == first ? site.operands[0] : site.operands[1]).negated) exact.push_back(s);
    }
    if (static_cast<int>(larger.size()) - (exact.empty() ? 1 : 0) < 1) return;

    const int node = dag_.size() + static_cast<int>(pairs_.size());
    pairs_.push_back({p, tie_of(p, key_of(first), key_of(second)), exact.empty() ? -1 : exact.front()});
    for (int s : sites)
      if (sites_[static_cast<std::size_t>(s)].operands.size() == 2) leave(p, s);
    for (int s : larger) {
      // Leave every pair of the site, replace the two operands by the shared one, enter again.
      for_each_pair(s, [&](const PairId& q) { leave(q, s); });
      Site& site = sites_[static_cast<std::size_t>(s)];
      std::vector<Operand> rest;
      bool first_negated = false, taken_first = false, taken_second = false;
      for (const Operand& o : site.operands) {
        if (!taken_first && o.id() == first) {
          taken_first = true;
          first_negated = o.negated;
        } else if (!taken_second && o.id() == second) {
          taken_second = true;
        } else {
          rest.push_back(o);
        }
      }
      rest.push_back({node, sum && first_negated, false});
      site.operands = std::move(rest);
      if (static_cast<int>(site.operands.size()) <= kLargestPairedArity)
        for_each_pair(s, [&](const PairId& q) { enter(q, s); });
    }
  }

  int build(ExpressionDag& out, int node) {
    int& slot = built_[static_cast<std::size_t>(node)];
    if (slot >= 0) return slot;
    int result = -1;
    if (node >= dag_.size()) {
      const Pair& pair = pairs_[static_cast<std::size_t>(node - dag_.size())];
      if (pair.definition_site >= 0) {
        result = build(out, sites_[static_cast<std::size_t>(pair.definition_site)].instruction);
      } else {
        const auto [sum, first, second, opposite] = pair.id;
        Instruction in;
        if (first < 0 || second < 0) {  // a · d⁻¹
          in.op = OpCode::quotient;
          in.args = {build(out, first < 0 ? second : first), build(out, first < 0 ? ~first : ~second)};
        } else {
          in.op = sum ? OpCode::sum : OpCode::product;
          in.args = {build(out, first), build(out, second)};
          if (sum) in.negated = {false, opposite};
        }
        result = out.append(std::move(in));
      }
    } else {
      Instruction in = dag_[node];
      const auto site = site_of_.find(node);
      if (site != site_of_.end()) {
        in.args.clear();
        in.negated.clear();
        int denominator = -1;
        for (const Operand& o : sites_[static_cast<std::size_t>(site->second)].operands) {
          if (o.inverse) {
            denominator = build(out, o.node);
            continue;
          }
          in.args.push_back(build(out, o.node));
          if (in.op == OpCode::sum) in.negated.push_back(o.negated);
        }
        if (in.op == OpCode::quotient) {  // the site of n / d: a product, over d if d⁻¹ is left
          in.op = OpCode::product;
          if (denominator >= 0) {
            Instruction q;
            q.op = OpCode::quotient;
            q.args = {in.args.size() == 1 ? in.args[0] : out.append(std::move(in)), denominator};
            in = std::move(q);
          }
        }
      } else {
        for (int& a : in.args) a = build(out, a);
      }
      result = out.append(std::move(in));
    }
    slot = result;
    return result;
  }

  const ExpressionDag& dag_;
  std::vector<Site> sites_;
  std::unordered_map<int, int> site_of_;  ///< instruction → site
  std::vector<Pair> pairs_;
  std::unordered_map<PairId, Sites, PairIdHash> sites_with_;
  std::priority_queue<std::tuple<int, std::uint64_t, PairId>> queue_;
  std::vector<int> built_;
};

}  // namespace

ExpressionDag share_common_arguments(const ExpressionDag& dag, std::vector<int>& outputs) {
  CommonArguments pass(dag, outputs);
  pass.share();
  return pass.rebuild(outputs);
}

}  // namespace nhc
