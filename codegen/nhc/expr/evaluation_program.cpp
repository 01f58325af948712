#include "nhc/expr/evaluation_program.hpp"

#include <climits>
#include <cmath>
#include <cstring>
#include <map>
#include <unordered_map>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

struct UnaryEntry {
  const char* name;
  double (*function)(double);
};
struct BinaryEntry {
  const char* name;
  double (*function)(double, double);
};
// The C library functions a `call` instruction may name, with their printed names.
const UnaryEntry kUnary[] = {
    {"std::sin", std::sin},     {"std::cos", std::cos},     {"std::tan", std::tan},   {"std::exp", std::exp},
    {"std::log", std::log},     {"std::sinh", std::sinh},   {"std::cosh", std::cosh}, {"std::tanh", std::tanh},
    {"std::asin", std::asin},   {"std::acos", std::acos},   {"std::atan", std::atan}, {"std::asinh", std::asinh},
    {"std::acosh", std::acosh}, {"std::atanh", std::atanh}, {"std::fabs", std::fabs}, {"std::sqrt", std::sqrt}};
const BinaryEntry kBinary[] = {{"std::pow", std::pow}, {"std::atan2", std::atan2}};

}  // namespace

double (*unary_function(const std::string& name))(double) {
  for (const UnaryEntry& e : kUnary)
    if (name == e.name) return e.function;
  return nullptr;
}

double (*binary_function(const std::string& name))(double, double) {
  for (const BinaryEntry& e : kBinary)
    if (name == e.name) return e.function;
  return nullptr;
}

EvaluationProgram::EvaluationProgram(const ExpressionDag& dag, const std::vector<Output>& outputs,
                                     const InputLocator& locate) {
  std::vector<int> roots;
  for (const Output& o : outputs) roots.push_back(o.instruction);
  // reachable() is increasing in index, which is topological: operands come first.
  const std::vector<int> reached = dag.reachable(roots);
  // First one register per instruction; allocate_registers() then lets registers whose value is
  // dead be reused, so that the registers a program touches stay few and in cache.
  std::unordered_map<int, int> register_of;
  for (int id : reached) register_of[id] = register_count_++;
  // sin and cos of one argument: one sincos call, as the compiler makes of the printed code.
  std::unordered_map<int, int> sine_of, cosine_of;  // argument instruction → the call
  for (int id : reached) {
    const Instruction& in = dag[id];
    if (in.op != OpCode::call || in.args.size() != 1) continue;
    if (in.name == "std::sin") sine_of[in.args[0]] = id;
    if (in.name == "std::cos") cosine_of[in.args[0]] = id;
  }
  std::unordered_map<int, bool> paired;  // call instruction → computed with its partner
  std::vector<int> pinned;               // the constants' registers
  for (int id : reached) {
    const Instruction& in = dag[id];
    const int target = register_of.at(id);
    auto reg = [&](std::size_t k) { return register_of.at(in.args[k]); };
    Operation op;
    op.target = target;
    if (in.op == OpCode::call && in.args.size() == 1 && (in.name == "std::sin" || in.name == "std::cos")) {
      if (paired.count(id)) continue;
      const auto& partners = in.name == "std::sin" ? cosine_of : sine_of;
      const auto partner = partners.find(in.args[0]);
      if (partner != partners.end()) {
        paired[partner->second] = true;
        op.code = Code::sincos;
        op.a = reg(0);
        op.target = in.name == "std::sin" ? target : register_of.at(partner->second);
        op.b = in.name == "std::sin" ? register_of.at(partner->second) : target;
        operations_.push_back(op);
        continue;
      }
    }
    switch (in.op) {
      case OpCode::constant:
        constants_.emplace_back(target, in.value);
        pinned.push_back(target);
        continue;
      case OpCode::input: {
        const InputLocation at = locate(in);
        op.code = Code::load;
        op.a = at.argument;
        op.b = at.index;
        break;
      }
      case OpCode::sum:
        if (in.args.size() == 2) {
          static constexpr Code codes[2][2] = {{Code::add, Code::subtract},
                                               {Code::negated_add, Code::negated_subtract}};
          op.code = codes[in.negated[0] ? 1 : 0][in.negated[1] ? 1 : 0];
          op.a = reg(0);
          op.b = reg(1);
          break;
        }
        [[fallthrough]];
      case OpCode::product:
        if (in.op == OpCode::product && in.args.size() == 2) {
          op.code = Code::multiply;
          op.a = reg(0);
          op.b = reg(1);
          break;
        }
        if (in.op == OpCode::product && in.args.size() == 3) {
          op.code = Code::multiply3;
          op.a = reg(0);
          op.b = reg(1);
          op.c = reg(2);
          break;
        }
        op.code = in.op == OpCode::sum ? Code::sum : Code::product;
        op.a = static_cast<int>(operands_.size());
        op.b = static_cast<int>(in.args.size());
        for (std::size_t k = 0; k < in.args.size(); ++k) {
          operands_.push_back(reg(k));
          negated_.push_back(in.op == OpCode::sum && in.negated[k] ? 1 : 0);
        }
        break;
      case OpCode::quotient:
        op.code = Code::quotient;
        op.a = reg(0);
        op.b = reg(1);
        break;
      case OpCode::negate:
        op.code = Code::negate;
        op.a = reg(0);
        break;
      case OpCode::square_root:
        op.code = Code::square_root;
        op.a = reg(0);
        break;
      case OpCode::integer_power:
        op.code = in.exponent == 2 ? Code::square : Code::power;
        op.a = reg(0);
        op.b = in.exponent;
        break;
      case OpCode::call:
        if (in.args.size() == 1 && unary_function(in.name)) {
          op.code = Code::call1;
          op.a = reg(0);
          op.b = static_cast<int>(unary_.size());
          unary_.push_back(unary_function(in.name));
        } else if (in.args.size() == 2 && binary_function(in.name)) {
          op.code = Code::call2;
          op.a = reg(0);
          op.c = reg(1);
          op.b = static_cast<int>(binary_.size());
          binary_.push_back(binary_function(in.name));
        } else {
          throw MathError("no numeric evaluation for " + in.name + " with " + std::to_string(in.args.size()) +
                          " arguments");
        }
        break;
      case OpCode::sign:
      case OpCode::step:
        op.code = in.op == OpCode::sign ? Code::sign : Code::step;
        op.a = reg(0);
        break;
    }
    operations_.push_back(op);
  }
  std::vector<int> kept;  // the outputs' registers: read by the stores at the end
  for (const Output& o : outputs) {
    Operation store;
    store.code = Code::store;
    store.target = o.slot;
    store.a = register_of.at(o.instruction);
    store.b = o.index;
    operations_.push_back(store);
    kept.push_back(store.a);
  }
  allocate_registers(pinned, kept);
  Operation halt;
  halt.code = Code::halt;
  operations_.push_back(halt);
}

void EvaluationProgram::allocate_registers(const std::vector<int>& pinned, const std::vector<int>& kept) {
  // Visits the registers an operation reads (read = true) or writes, by reference.
  auto visit = [this](Operation& op, bool read, auto&& f) {
    switch (op.code) {
      case Code::load:
        if (!read) f(op.target);
        break;
      case Code::sum:
      case Code::product:
        if (read)
          for (int k = op.a; k < op.a + op.b; ++k) f(operands_[static_cast<std::size_t>(k)]);
        else f(op.target);
        break;
      case Code::add:
      case Code::subtract:
      case Code::negated_add:
      case Code::negated_subtract:
      case Code::multiply:
      case Code::quotient:
        if (read) {
          f(op.a);
          f(op.b);
        } else {
          f(op.target);
        }
        break;
      case Code::multiply3:
        if (read) {
          f(op.a);
          f(op.b);
          f(op.c);
        } else {
          f(op.target);
        }
        break;
      case Code::call2:
        if (read) {
          f(op.a);
          f(op.c);
        } else {
          f(op.target);
        }
        break;
      case Code::negate:
      case Code::square_root:
      case Code::square:
      case Code::power:
      case Code::call1:
      case Code::sign:
      case Code::step:
        if (read) f(op.a);
        else f(op.target);
        break;
      case Code::sincos:
        if (read) {
          f(op.a);
        } else {
          f(op.target);
          f(op.b);
        }
        break;
      case Code::store:
        if (read) f(op.a);
        break;
      case Code::halt:
        break;
    }
  };
  const auto n = static_cast<std::size_t>(register_count_);
  std::vector<int> last_use(n, -1);
  for (std::size_t i = 0; i < operations_.size(); ++i)
    visit(operations_[i], true, [&](int v) { last_use[static_cast<std::size_t>(v)] = static_cast<int>(i); });
  // Constants are written once per thread, outputs read by the stores at the end: never reused.
  for (int v : kept) last_use[static_cast<std::size_t>(v)] = INT_MAX;
  for (int v : pinned) last_use[static_cast<std::size_t>(v)] = INT_MAX;
  std::vector<int> physical(n, -1);
  int count = 0;
  for (int v : pinned) physical[static_cast<std::size_t>(v)] = count++;
  for (auto& [at, value] : constants_) at = physical[static_cast<std::size_t>(at)];
  std::vector<int> free, unread;
  for (std::size_t i = 0; i < operations_.size(); ++i) {
    Operation& op = operations_[i];
    // Targets are taken before the operands are freed: no operation writes a register it reads.
    visit(op, false, [&](int& v) {
      int& p = physical[static_cast<std::size_t>(v)];
      if (p < 0) {
        if (free.empty()) {
          p = count++;
        } else {
          p = free.back();
          free.pop_back();
        }
      }
      if (last_use[static_cast<std::size_t>(v)] < 0) {  // never read (one of a sincos): free after this operation
        unread.push_back(p);
        last_use[static_cast<std::size_t>(v)] = INT_MAX;
      }
      v = p;
    });
    free.insert(free.end(), unread.begin(), unread.end());
    unread.clear();
    visit(op, true, [&](int& v) {
      const auto u = static_cast<std::size_t>(v);
      v = physical[u];
      if (last_use[u] == static_cast<int>(i)) {
        free.push_back(physical[u]);
        last_use[u] = INT_MAX;  // freed once, however often this operation reads it
      }
    });
  }
  register_count_ = count;
}

// ---------------------------------------------------------------------------------------------
// The program as bytes: little-endian 32-bit words, doubles by their 64 bits, functions by name.

namespace {

void put_word(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xffu));
}
void put_int(std::string& out, int v) { put_word(out, static_cast<std::uint32_t>(v)); }
void put_name(std::string& out, const char* name) {
  put_word(out, static_cast<std::uint32_t>(std::strlen(name)));
  out += name;
}

/// Reads what put_* wrote; false once the bytes run out.
struct ByteReader {
  std::string_view bytes;
  std::size_t pos = 0;
  bool word(std::uint32_t& v) {
    if (bytes.size() - pos < 4) return false;
    v = 0;
    for (int k = 0; k < 4; ++k) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[pos + k])) << (8 * k);
    pos += 4;
    return true;
  }
  bool integer(int& v) {
    std::uint32_t w = 0;
    if (!word(w)) return false;
    v = static_cast<int>(w);
    return true;
  }
  /// A count of items of at least `item_bytes` each that the remaining bytes can hold.
  bool count(std::size_t& n, std::size_t item_bytes) {
    std::uint32_t w = 0;
    if (!word(w) || w > (bytes.size() - pos) / item_bytes) return false;
    n = w;
    return true;
  }
  bool name(std::string& text) {
    std::size_t n = 0;
    if (!count(n, 1)) return false;
    text.assign(bytes.substr(pos, n));
    pos += n;
    return true;
  }
};

template <typename Entry, typename F>
const char* name_of(const Entry& table, F function) {
  for (const auto& e : table)
    if (e.function == function) return e.name;
  return nullptr;
}

}  // namespace

std::string EvaluationProgram::to_bytes() const {
  std::string out;
  put_int(out, register_count_);
  put_word(out, static_cast<std::uint32_t>(operations_.size()));
  for (const Operation& op : operations_) {
    put_int(out, static_cast<int>(op.code));
    put_int(out, op.target);
    put_int(out, op.a);
    put_int(out, op.b);
    put_int(out, op.c);
  }
  put_word(out, static_cast<std::uint32_t>(operands_.size()));
  for (std::size_t k = 0; k < operands_.size(); ++k) {
    put_int(out, operands_[k]);
    put_int(out, negated_[k]);
  }
  put_word(out, static_cast<std::uint32_t>(unary_.size()));
  for (auto f : unary_) put_name(out, name_of(kUnary, f));
  put_word(out, static_cast<std::uint32_t>(binary_.size()));
  for (auto f : binary_) put_name(out, name_of(kBinary, f));
  put_word(out, static_cast<std::uint32_t>(constants_.size()));
  for (const auto& [at, value] : constants_) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    put_int(out, at);
    put_word(out, static_cast<std::uint32_t>(bits));
    put_word(out, static_cast<std::uint32_t>(bits >> 32));
  }
  return out;
}

std::optional<EvaluationProgram> EvaluationProgram::from_bytes(std::string_view bytes, int arguments, int outputs) {
  EvaluationProgram p;
  ByteReader in{bytes};
  std::size_t n = 0;
  if (!in.integer(p.register_count_) || p.register_count_ < 0 || !in.count(n, 20)) return std::nullopt;
  p.operations_.resize(n);
  for (Operation& op : p.operations_) {
    int code = 0;
    if (!in.integer(code) || code < 0 || code > static_cast<int>(Code::halt) || !in.integer(op.target) ||
        !in.integer(op.a) || !in.integer(op.b) || !in.integer(op.c))
      return std::nullopt;
    op.code = static_cast<Code>(code);
  }
  if (!in.count(n, 8)) return std::nullopt;
  p.operands_.resize(n);
  p.negated_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    int negated = 0;
    if (!in.integer(p.operands_[k]) || !in.integer(negated) || negated < 0 || negated > 1) return std::nullopt;
    p.negated_[k] = static_cast<char>(negated);
  }
  std::string name;
  if (!in.count(n, 4)) return std::nullopt;
  for (std::size_t k = 0; k < n; ++k) {
    if (!in.name(name) || !unary_function(name)) return std::nullopt;
    p.unary_.push_back(unary_function(name));
  }
  if (!in.count(n, 4)) return std::nullopt;
  for (std::size_t k = 0; k < n; ++k) {
    if (!in.name(name) || !binary_function(name)) return std::nullopt;
    p.binary_.push_back(binary_function(name));
  }
  if (!in.count(n, 12)) return std::nullopt;
  for (std::size_t k = 0; k < n; ++k) {
    int at = 0;
    std::uint32_t low = 0, high = 0;
    if (!in.integer(at) || !in.word(low) || !in.word(high)) return std::nullopt;
    const std::uint64_t bits = (static_cast<std::uint64_t>(high) << 32) | low;
    double value = 0;
    std::memcpy(&value, &bits, sizeof value);
    p.constants_.emplace_back(at, value);
  }
  if (in.pos != bytes.size()) return std::nullopt;

  // Every index the program follows, within what it has and what run() is given.
  const int registers = p.register_count_;
  auto reg = [registers](int v) { return v >= 0 && v < registers; };
  for (const auto& [at, value] : p.constants_)
    if (!reg(at)) return std::nullopt;
  for (int v : p.operands_)
    if (!reg(v)) return std::nullopt;
  if (!p.operations_.empty() && p.operations_.back().code != Code::halt) return std::nullopt;
  for (std::size_t i = 0; i < p.operations_.size(); ++i) {
    const Operation& op = p.operations_[i];
    bool sound = true;
    switch (op.code) {
      case Code::load:
        sound = reg(op.target) && op.a >= 0 && op.a < arguments && op.b >= 0;
        break;
      case Code::sum:
      case Code::product:
        sound = reg(op.target) && op.a >= 0 && op.b >= 1 &&
                static_cast<std::size_t>(op.a) + static_cast<std::size_t>(op.b) <= p.operands_.size();
        break;
      case Code::add:
      case Code::subtract:
      case Code::negated_add:
      case Code::negated_subtract:
      case Code::multiply:
      case Code::quotient:
        sound = reg(op.target) && reg(op.a) && reg(op.b);
        break;
      case Code::multiply3:
        sound = reg(op.target) && reg(op.a) && reg(op.b) && reg(op.c);
        break;
      case Code::negate:
      case Code::square_root:
      case Code::square:
      case Code::sign:
      case Code::step:
        sound = reg(op.target) && reg(op.a);
        break;
      case Code::power:
        sound = reg(op.target) && reg(op.a) && op.b >= 1;
        break;
      case Code::call1:
        sound = reg(op.target) && reg(op.a) && op.b >= 0 && static_cast<std::size_t>(op.b) < p.unary_.size();
        break;
      case Code::call2:
        sound =
            reg(op.target) && reg(op.a) && reg(op.c) && op.b >= 0 && static_cast<std::size_t>(op.b) < p.binary_.size();
        break;
      case Code::sincos:
        sound = reg(op.target) && reg(op.a) && reg(op.b);
        break;
      case Code::store:
        sound = op.target >= 0 && op.target < outputs && reg(op.a) && op.b >= 0;
        break;
      case Code::halt:
        sound = i + 1 == p.operations_.size();
        break;
    }
    if (!sound) return std::nullopt;
  }
  return p;
}

// The dispatch: GCC's and Clang's labels as values (one indirect jump per operation, each
// predicted on its own), else a switch.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#endif

void EvaluationProgram::run(const double* const* arguments, double* const* outputs,
                            std::vector<double>& registers) const {
  if (operations_.empty()) return;
  if (registers.size() != static_cast<std::size_t>(register_count_)) {
    registers.assign(static_cast<std::size_t>(register_count_), 0.0);
    for (const auto& [at, value] : constants_) registers[static_cast<std::size_t>(at)] = value;
  }
  double* r = registers.data();
  const int* operand = operands_.data();
  const char* minus = negated_.data();
  const Operation* op = operations_.data();
  // Each case computes as the printed code does (cpp_printer.cpp), left to right, so that the
  // interpreted and the compiled model agree to the last bit where the compiler keeps IEEE order.
#if defined(__GNUC__)
  static const void* const labels[] = {
      &&op_load,     &&op_add,       &&op_subtract, &&op_negated_add, &&op_negated_subtract, &&op_sum,
      &&op_multiply, &&op_multiply3, &&op_product,  &&op_quotient,    &&op_negate,           &&op_square_root,
      &&op_square,   &&op_power,     &&op_call1,    &&op_call2,       &&op_sincos,           &&op_sign,
      &&op_step,     &&op_store,     &&op_halt};
  static_assert(sizeof(labels) / sizeof(labels[0]) == static_cast<int>(Code::halt) + 1);
#define NHC_OP(name) op_##name:
#define NHC_NEXT goto* labels[static_cast<int>((++op)->code)]
  goto* labels[static_cast<int>(op->code)];
#else
#define NHC_OP(name) case Code::name:
#define NHC_NEXT \
  ++op;          \
  continue
  for (;;) {
    switch (op->code) {
#endif
  NHC_OP(load) r[op->target] = arguments[op->a][op->b];
  NHC_NEXT;
  NHC_OP(add) r[op->target] = r[op->a] + r[op->b];
  NHC_NEXT;
  NHC_OP(subtract) r[op->target] = r[op->a] - r[op->b];
  NHC_NEXT;
  NHC_OP(negated_add) r[op->target] = -r[op->a] + r[op->b];
  NHC_NEXT;
  NHC_OP(negated_subtract) r[op->target] = -r[op->a] - r[op->b];
  NHC_NEXT;
  NHC_OP(sum) {
    const int* k = operand + op->a;
    const char* s = minus + op->a;
    double v = s[0] ? -r[k[0]] : r[k[0]];
    for (int j = 1; j < op->b; ++j) v = s[j] ? v - r[k[j]] : v + r[k[j]];
    r[op->target] = v;
  }
  NHC_NEXT;
  NHC_OP(multiply) r[op->target] = r[op->a] * r[op->b];
  NHC_NEXT;
  NHC_OP(multiply3) r[op->target] = r[op->a] * r[op->b] * r[op->c];
  NHC_NEXT;
  NHC_OP(product) {
    const int* k = operand + op->a;
    double v = r[k[0]];
    for (int j = 1; j < op->b; ++j) v *= r[k[j]];
    r[op->target] = v;
  }
  NHC_NEXT;
  NHC_OP(quotient) r[op->target] = r[op->a] / r[op->b];
  NHC_NEXT;
  NHC_OP(negate) r[op->target] = -r[op->a];
  NHC_NEXT;
  NHC_OP(square_root) r[op->target] = std::sqrt(r[op->a]);
  NHC_NEXT;
  NHC_OP(square) r[op->target] = r[op->a] * r[op->a];
  NHC_NEXT;
  NHC_OP(power) {
    const double base = r[op->a];
    double v = base;
    for (int j = 1; j < op->b; ++j) v *= base;
    r[op->target] = v;
  }
  NHC_NEXT;
  NHC_OP(call1) r[op->target] = unary_[static_cast<std::size_t>(op->b)](r[op->a]);
  NHC_NEXT;
  NHC_OP(call2) r[op->target] = binary_[static_cast<std::size_t>(op->b)](r[op->a], r[op->c]);
  NHC_NEXT;
  NHC_OP(sincos) sincos(r[op->a], &r[op->target], &r[op->b]);
  NHC_NEXT;
  NHC_OP(sign) r[op->target] = static_cast<double>((0.0 < r[op->a]) - (r[op->a] < 0.0));
  NHC_NEXT;
  NHC_OP(step) r[op->target] = r[op->a] < 0.0 ? 0.0 : (0.0 < r[op->a] ? 1.0 : 0.5);
  NHC_NEXT;
  NHC_OP(store) outputs[op->target][op->b] = r[op->a];
  NHC_NEXT;
  NHC_OP(halt) return;
#if !defined(__GNUC__)
}
}
#endif
#undef NHC_OP
#undef NHC_NEXT
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace nhc
