#include "nhc/analysis/numeric_program.hpp"

#include <cmath>
#include <map>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> input_names(const std::vector<GiNaC::ex>& inputs) {
  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> names;
  for (std::size_t k = 0; k < inputs.size(); ++k) names[inputs[k]] = std::to_string(k);
  return names;
}

/// The C++ functions the lowering names (jet/expression_dag.cpp), as doubles.
double call(const std::string& name, const std::vector<double>& a) {
  static const std::map<std::string, double (*)(double)> unary = {
      {"std::sin", std::sin},     {"std::cos", std::cos},     {"std::tan", std::tan},   {"std::exp", std::exp},
      {"std::log", std::log},     {"std::sinh", std::sinh},   {"std::cosh", std::cosh}, {"std::tanh", std::tanh},
      {"std::asin", std::asin},   {"std::acos", std::acos},   {"std::atan", std::atan}, {"std::asinh", std::asinh},
      {"std::acosh", std::acosh}, {"std::atanh", std::atanh}, {"std::fabs", std::fabs}, {"std::sqrt", std::sqrt}};
  if (a.size() == 1) {
    const auto f = unary.find(name);
    if (f != unary.end()) return f->second(a[0]);
  }
  if (a.size() == 2 && name == "std::pow") return std::pow(a[0], a[1]);
  if (a.size() == 2 && name == "std::atan2") return std::atan2(a[0], a[1]);
  throw MathError("no numeric evaluation for " + name + " with " + std::to_string(a.size()) + " arguments");
}

}  // namespace

NumericProgram::NumericProgram(const std::vector<GiNaC::ex>& inputs) : dag_(input_names(inputs)) {}

int NumericProgram::add(const GiNaC::ex& e, std::string label) {
  outputs_.push_back(dag_.add(e));
  labels_.push_back(std::move(label));
  prepared_ = false;
  return static_cast<int>(outputs_.size()) - 1;
}

void NumericProgram::prepare() const {
  order_ = dag_.reachable(outputs_);
  input_index_.assign(static_cast<std::size_t>(dag_.size()), -1);
  for (int id : order_)
    if (dag_[id].op == OpCode::input) input_index_[static_cast<std::size_t>(id)] = std::stoi(dag_[id].name);
  prepared_ = true;
}

std::vector<double> NumericProgram::evaluate(const std::vector<double>& values, const std::string& what) const {
  std::vector<double> out = values_at(values);
  for (std::size_t k = 0; k < out.size(); ++k)
    if (!std::isfinite(out[k]))
      throw MathError(labels_[k].empty() ? what + " is not finite there (output " + std::to_string(k + 1) + ")"
                                         : labels_[k] + " is not finite there");
  return out;
}

std::vector<double> NumericProgram::values_at(const std::vector<double>& values) const {
  if (!prepared_) prepare();
  std::vector<double> v(static_cast<std::size_t>(dag_.size()), 0.0);
  std::vector<double> arguments;
  auto at = [&](int id) { return v[static_cast<std::size_t>(id)]; };
  for (int id : order_) {
    const Instruction& in = dag_[id];
    double r = 0.0;
    switch (in.op) {
      case OpCode::constant: r = in.value; break;
      case OpCode::input: r = values.at(static_cast<std::size_t>(input_index_[static_cast<std::size_t>(id)])); break;
      case OpCode::sum:
        for (std::size_t k = 0; k < in.args.size(); ++k) r += in.negated[k] ? -at(in.args[k]) : at(in.args[k]);
        break;
      case OpCode::product:
        r = 1.0;
        for (int a : in.args) r *= at(a);
        break;
      case OpCode::quotient: r = at(in.args[0]) / at(in.args[1]); break;
      case OpCode::negate: r = -at(in.args[0]); break;
      case OpCode::square_root: r = std::sqrt(at(in.args[0])); break;
      case OpCode::integer_power: {
        const double base = at(in.args[0]);
        r = base;
        for (int k = 1; k < in.exponent; ++k) r *= base;  // as the generated code multiplies
        break;
      }
      case OpCode::call:
        arguments.clear();
        for (int a : in.args) arguments.push_back(at(a));
        r = call(in.name, arguments);
        break;
      case OpCode::sign: r = at(in.args[0]) > 0 ? 1.0 : (at(in.args[0]) < 0 ? -1.0 : 0.0); break;
      case OpCode::step: r = at(in.args[0]) > 0 ? 1.0 : (at(in.args[0]) < 0 ? 0.0 : 0.5); break;
    }
    v[static_cast<std::size_t>(id)] = r;
  }
  std::vector<double> out;
  out.reserve(outputs_.size());
  for (int id : outputs_) out.push_back(at(id));
  return out;
}

}  // namespace nhc
