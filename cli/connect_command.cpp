// nhc connect SCENE --to x=1,y=0,z=0.25 --t-end T [--free x'(0),y'(0),lambda1(0)] [--segments K]
//             [--model M] [--initial NAME=VALUE]... [--rtol R] [--atol A] [--tolerance E] [--max-iterations N]
//             [-o FILE.csv]
//
// A boundary-value problem (docs/connect.md): the free initial values that take the scene's
// motion to the target states at T, by Newton's method on the shooting function with the IDAS
// sensitivities as its Jacobian (nhc::connect). Prints the values found, the iterations and the
// final miss, writes the trajectory (simulate's CSV columns). No convergence or a singular
// shooting Jacobian: exit 3 with the words of nhc::connect::ShootingFailure.
#include <cmath>
#include <fstream>
#include <iostream>
#include <regex>

#include "commands.hpp"
#include "nhc/app/model_requirements.hpp"
#include "flag_rules.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/connect/shooting.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/app/initial_values.hpp"
#include "nhc/base/number_text.hpp"
#include "run_flags.hpp"

namespace nhc::cli {

namespace {

struct ConnectOptions {
  std::string scene_path;
  std::string model;
  std::vector<std::string> to;
  std::vector<std::string> free;
  std::vector<std::string> initial;  ///< --initial NAME=VALUE
  double t_end = 0;
  int segments = 1;
  std::optional<double> rtol, atol;
  double tolerance = 1e-9;
  int max_iterations = 50;
  int outputs = 200;
  std::string output;
};

/// The state names of `model`, for messages: "x, x', y, y', z, lambda1".
std::string state_list(const runtime::Model& model, bool differential_only, const std::string& suffix) {
  std::string out;
  for (int i = 0; i < model.n_states(); ++i)
    if (!differential_only || model.is_differential(i)) out += (out.empty() ? "" : ", ") + model.state_name(i) + suffix;
  return out;
}

int state_named(const runtime::Model& model, const std::string& name) {
  for (int i = 0; i < model.n_states(); ++i)
    if (model.state_name(i) == name) return i;
  return -1;
}

std::vector<connect::Condition> parse_targets(const runtime::Model& model, const std::vector<std::string>& items) {
  auto bad = [](const std::string& message) { throw InputError({"--to", 0, 0}, message); };
  std::vector<connect::Condition> conditions;
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) bad("'" + item + "' is not NAME=VALUE");
    const std::string name = item.substr(0, eq), text = item.substr(eq + 1);
    const int state = state_named(model, name);
    if (state < 0)
      bad("unknown name '" + name + "': the states of the " + model.model_name() + " model are " +
          state_list(model, false, ""));
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(value))
      bad("'" + text + "' (for " + name + ") is not a finite number");
    for (const connect::Condition& c : conditions)
      if (c.state == state) bad(name + " is given twice");
    conditions.push_back({state, name, value});
  }
  if (conditions.empty()) bad("no target given");
  return conditions;
}

/// FILE:LINE:COLUMN of `variable = […]` in the scene's [initial] table (the file's position when
/// the line is not found, e.g. an inline table).
SourceLocation initial_entry(const std::string& path, const std::string& variable) {
  std::ifstream in(path);
  std::string line;
  bool in_initial = false;
  const std::regex key("^\\s*" + variable + "\\s*=");
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find('[') != std::string::npos && std::regex_search(line, std::regex("^\\s*\\[")))
      in_initial = std::regex_search(line, std::regex("^\\s*\\[\\s*initial\\s*\\]"));
    else if (in_initial && std::regex_search(line, key))
      return {path, number, static_cast<int>(line.find(variable)) + 1};
  }
  return {path, 0, 0};
}

std::vector<int> parse_free(const runtime::Model& model, const runtime::InitialState& initial,
                            const std::vector<std::string>& names, const std::string& scene_path,
                            const std::vector<std::string>& initial_flags) {
  std::vector<int> states;
  for (const std::string& name : names) {
    const std::string suffix = "(0)";
    const bool has_suffix = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), 3, suffix) == 0;
    const int state = has_suffix ? state_named(model, name.substr(0, name.size() - suffix.size())) : -1;
    if (state < 0)
      throw InputError({"--free", 0, 0}, "unknown initial value '" + name + "': the " + model.model_name() +
                                             " model's initial values are " + state_list(model, true, "(0)"));
    if (!model.is_differential(state))
      throw InputError({"--free", 0, 0}, name + " belongs to an algebraic state: it follows from the others");
    if (initial.given[static_cast<size_t>(state)])
      for (const std::string& a : initial_flags)
        if (a.substr(0, a.find('=')) == model.state_name(state))
          throw InputError({"--initial", 0, 0},
                           a + ": " + name + " is given here, so it cannot be free (--free " + name + ")");
    if (initial.given[static_cast<size_t>(state)])
      throw InputError(initial_entry(scene_path, model.variable_name(model.table().state_variable[state])),
                       name + " is given in the scene's [initial], so it cannot be free (--free " + name + ")");
    if (std::find(states.begin(), states.end(), state) != states.end())
      throw InputError({"--free", 0, 0}, name + " is named twice");
    states.push_back(state);
  }
  return states;
}

void print_result(const connect::ShootingProblem& problem, const connect::ShootingResult& result) {
  const runtime::Model& model = problem.model;
  for (const connect::Iteration& it : result.history)
    std::cout << "  iteration " << it.number << ": miss " << base::number_text(it.miss, 3)
              << (it.number > 0 ? ", step " + base::number_text(it.step, 3) : std::string()) << ", Jacobian rank "
              << it.rank << "\n";
  std::cout << "  converged in " << result.history.back().number << " iteration"
            << (result.history.back().number == 1 ? "" : "s") << ", final miss " << base::number_text(result.miss, 3)
            << "\n";
  if (result.minimum_norm)
    std::cout << "  more free values than conditions: minimum-norm Newton steps (the solution found is one of many)\n";
  if (result.least_squares) std::cout << "  more conditions than free values: least-squares (Gauss-Newton) steps\n";
  std::cout << "  values found:\n";
  for (size_t k = 0; k < problem.free_states.size(); ++k)
    std::cout << "    " << connect::free_value_name(model, problem.free_states[k]) << " = "
              << base::number_text(result.values[k], 15) << "\n";
}

}  // namespace

CommandRunner add_connect_command(CLI::App& app) {
  auto options = std::make_shared<ConnectOptions>();
  CLI::App* sub = app.add_subcommand(
      "connect", "find the free initial values that take a scene's motion to target states at T (shooting)");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--to", options->to, "target states at T, e.g. x=1,y=0,z=0.25")->delimiter(',')->required();
  sub->add_option("--t-end", options->t_end, "the time T at which the target is to be reached")
      ->required()
      ->check(flag_rules::finite());
  sub->add_option("--free", options->free,
                  "the free initial values, e.g. x'(0),y'(0),lambda1(0) (default: every initial value the "
                  "Sigma-method needs that the scene does not give)")
      ->delimiter(',');
  sub->add_option("--segments", options->segments, "multiple shooting on K equal intervals (default 1)")
      ->check(flag_rules::count(1, 1000));
  sub->add_option("--model,-m", options->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  add_initial_flag(sub, options->initial);
  sub->add_option("--rtol", options->rtol, "relative tolerance of the integrations (default: [simulate] rtol)")
      ->check(flag_rules::relative_tolerance());
  sub->add_option("--atol", options->atol, "absolute tolerance of the integrations (default: [simulate] atol)")
      ->check(flag_rules::absolute_tolerance());
  sub->add_option("--tolerance", options->tolerance, "converged when every |miss| <= E (1 + |target|) (default 1e-9)")
      ->check(flag_rules::positive());
  sub->add_option("--max-iterations", options->max_iterations, "Newton iterations (default 50)")
      ->check(flag_rules::count(1, 10000));
  sub->add_option("--outputs", options->outputs, "number of output intervals of the trajectory (default 200)")
      ->check(flag_rules::count(1, flag_rules::kMaxOutputs));
  sub->add_option("-o,--output", options->output, "CSV file for the trajectory found");

  return [options]() {
    Scene scene = load_scene(options->scene_path);
    apply_initial_flags(scene, options->initial);  // given values: not free by default
    if (!options->output.empty()) check_output_file(options->output, {options->scene_path});
    const ModelKind kind = model_or_default(scene, options->model);
    app::require_model_inputs(scene, kind);  // exit 2 at the scene, as simulate
    app::refuse_inputs(scene, "boundary-value problems", "nhc connect");
    app::run_t_end(scene, options->t_end, "--t-end");  // required and checked finite by the flag
    const jit::LoadedModel built = jit::build(scene, kind);
    const runtime::Model& model = built.model();

    connect::ShootingProblem problem{model,
                                     model.default_parameters(),
                                     app::initial_state_of(scene, model),
                                     {},
                                     {},
                                     1,
                                     1,
                                     runtime::IntegratorOptions{},
                                     1e-9,
                                     50,
                                     200};
    problem.conditions = parse_targets(model, options->to);
    problem.free_states =
        options->free.empty()
            ? connect::default_free_states(model, problem.parameters, problem.initial)
            : parse_free(model, problem.initial, options->free, options->scene_path, options->initial);
    if (problem.free_states.empty())
      throw InputError({"--free", 0, 0}, "no free initial values: the scene gives every one the " + to_string(kind) +
                                             " model needs; name some with --free");
    problem.t_end = options->t_end;
    problem.segments = options->segments;
    problem.integrator.rtol = options->rtol.value_or(scene.simulate.rtol);
    problem.integrator.atol = options->atol.value_or(scene.simulate.atol);
    problem.tolerance = options->tolerance;
    problem.max_iterations = options->max_iterations;
    problem.outputs = options->outputs;

    std::cout << "nhc connect: " << scene.name << ", model " << to_string(kind) << ", to ";
    for (size_t c = 0; c < problem.conditions.size(); ++c)
      std::cout << (c ? ", " : "") << problem.conditions[c].name << " = " << problem.conditions[c].value;
    std::cout << " at T = " << problem.t_end << "; free ";
    for (size_t k = 0; k < problem.free_states.size(); ++k)
      std::cout << (k ? ", " : "") << connect::free_value_name(model, problem.free_states[k]);
    std::cout << (options->free.empty() ? " (default)" : "") << "; " << problem.segments << " segment"
              << (problem.segments == 1 ? "" : "s") << "\n";
    std::cout.flush();

    connect::ShootingResult result;
    try {
      result = connect::connect(problem);
    } catch (const connect::ShootingFailure& failure) {
      std::cerr << "nhc: error: connect: " << failure.what() << "\n";
      return kExitMathFailure;
    } catch (const base::SolverError& failure) {
      std::cerr << "nhc: error: connect: the integration failed: " << failure.what() << "\n";
      return kExitMathFailure;
    }
    print_result(problem, result);
    if (!options->output.empty()) {
      write_file_atomically(options->output, [&](std::ostream& out) {
        runtime::write_csv(out, model, problem.parameters, result.trajectory);
      });
      std::cout << "  wrote " << options->output << " (" << result.trajectory.size() << " rows)\n";
    }
    return kExitOk;
  };
}

}  // namespace nhc::cli
