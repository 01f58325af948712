#pragma once
/// \file scene.hpp
/// \brief A scene: one mechanical system as the user wrote it, with its expressions parsed
/// onto a JetSpace. Produced by load_scene() from TOML, or built in code.

#include <ginac/ginac.h>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nhc/expr/jet_space.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/model_kind.hpp"
#include "nhc/scene/scene_visual.hpp"

namespace nhc {

/// A number of the experiment that the scene may write as a constant expression of its
/// parameters (`mu = "muT"`, `period = "2*h"`, `t_end = "T"`): the text as written ("" for a
/// number) and its place. The number beside it holds its value at the scene's parameter values;
/// app::set_parameter_values() re-evaluates it whenever a run's parameters are set (--set, set=,
/// an ensemble's or a study's values), and refuses a value the place does not allow there.
struct NumberExpression {
  std::string text;
  SourceLocation where;
  bool empty() const { return text.empty(); }
};

/// Initial data: t0 and, per coordinate or multiplier, [value, 1st derivative, …].
struct InitialData {
  double t0 = 0.0;
  NumberExpression t0_expression;
  std::map<std::string, std::vector<double>> values;
  /// The text of values written as expressions (`thr = [0.0, "v/rR"]`), per entry of `values`
  /// ("" for a number): reevaluate_initial_expressions() recomputes them from the parameters.
  std::map<std::string, std::vector<std::string>> expressions;
  /// Given values that --repair-initial must not move ([initial] fixed = ["x", "y'"]).
  std::vector<std::string> fixed;
};

struct SimulateSettings {
  std::optional<ModelKind> model;
  double t_end = 1.0;
  double rtol = 1e-8;
  double atol = 1e-10;
  std::optional<int> outputs;          ///< output intervals ([simulate] outputs), default 200
  std::optional<double> max_step;      ///< IDA's largest step ([simulate] max_step)
  std::optional<double> initial_step;  ///< IDA's first step ([simulate] initial_step)
  /// The keys written as expressions of the parameters (NumberExpression).
  NumberExpression t_end_expression, rtol_expression, atol_expression, max_step_expression, initial_step_expression;
};

/// One entry of [invariants] or [outputs]: a named quantity of t, parameters, q, q', … and the
/// multipliers, written as a CSV column. A model that does not compute a quantity it uses (a
/// multiplier of the suslov model, λ' of the chetaev model) leaves the entry out with a note,
/// unless the scene marks it `required` (`E = { expression = "…", required = true }`).
struct SceneQuantity {
  std::string name;
  GiNaC::ex expression;   ///< of t, parameters, q, q', …, λ
  SourceLocation where;   ///< the expression's place in the scene file
  bool required = false;  ///< a model that cannot compute it is refused, not spared the column
};
using SceneOutput = SceneQuantity;

/// One entry of [events]: a zero crossing of `expression` (of t, parameters, q, q', …, λ) in
/// `direction`, located by the integrator's root finding (docs/scenes.md, "[events]").
enum class EventDirection { up, down, any };
enum class EventAction { stop, record };
struct SceneEvent {
  std::string name;
  GiNaC::ex expression;
  std::string text;      ///< as written
  SourceLocation where;  ///< the expression's place in the scene file (or the flag)
  EventDirection direction = EventDirection::any;
  EventAction action = EventAction::stop;
  /// Also met at t0 when the value starts below zero (a contact that slips from the start).
  bool met_below_at_start = false;
};

/// One entry of [contacts]: the normal force (an expression, or a multiplier of a holonomic
/// contact constraint), the rolling constraints whose multipliers are the tangential force's
/// components, the friction coefficient and what a slip does (docs/scenes.md, "Contacts";
/// docs/contacts.md).
enum class SlipAction { stop, slide };
struct SceneContact {
  std::string name;
  GiNaC::ex normal;         ///< F_n(t, q, q', …, λ)
  std::string normal_text;  ///< as written
  SourceLocation where;     ///< the contact's table in the scene file
  SourceLocation on_slip_where;
  std::vector<int> rolling;  ///< 0-based constraint indices: the slip velocity's components
  double mu = 0;
  NumberExpression mu_expression;  ///< mu written through the parameters
  SlipAction on_slip = SlipAction::stop;
};

/// [reference]: closed forms q(t) of coordinates, for every model, and per model
/// ([reference.vakonomic]) where the models' motions differ.
struct SceneReference {
  using Entries = std::vector<std::pair<int, GiNaC::ex>>;  ///< coordinate → q(t)
  Entries all;
  std::map<ModelKind, Entries> per_model;
  /// The closed forms for `model`: its own table, completed by the plain one for the coordinates
  /// it does not name; in coordinate order.
  Entries for_model(ModelKind model) const;
  bool empty() const { return all.empty() && per_model.empty(); }
};

/// One entry of [inputs]: a named signal u(t) that drives the model (a torque, a prescribed rate).
/// The equations hold the symbol u (JetSpace::input); `default_signal` (of t and parameters) is
/// what it is unless a run replaces it (`nhc simulate --input`, a callback from C++).
struct SceneInput {
  std::string name;
  GiNaC::ex default_signal;
  SourceLocation where;  ///< the entry in the scene file
  /// A feedback law u(t, q, q') (an [inputs] expression of coordinates): compiled into the
  /// equations in place of the input's symbol (closed loop), so no run fills it in and its
  /// default_signal is 0. Empty for a signal of t.
  GiNaC::ex law;
  bool feedback = false;
};

/// [controller]: a sampled (discrete-time) controller (docs/scenes.md, "Sampled controllers").
/// At each sample t_k = t0 + k*period it reads the state the run reached,
/// sets the inputs it drives (held until the next sample) and its discrete states' next values.
struct SceneControllerState {
  std::string name;
  double initial = 0;                   ///< its value at t0
  GiNaC::symbol symbol;                 ///< the name in the controller's expressions
  SourceLocation where;                 ///< the entry of `states`
  NumberExpression initial_expression;  ///< `initial` written through the parameters
};
/// An entry of `inputs` (target: the input's index in JetSpace::inputs()) or of `update`
/// (target: the state's index in SceneController::states).
struct SceneControllerLaw {
  int target = 0;
  std::string name;
  GiNaC::ex expression;  ///< of t, parameters, coordinates and derivatives, the states (definitions substituted)
  std::string text;      ///< as written
  SourceLocation where;  ///< the expression's place in the scene file
};
/// `mpc = { horizon = H, intervals = N, … }` of [controller]: model predictive control
/// (docs/mpc.md). At each sample the scene's [optimize] problem over [t_k, t_k + horizon] on N
/// equal intervals, from the state reached; its first input held to the next sample.
struct SceneMpc {
  bool present = false;
  double horizon = 0;
  int intervals = 0;
  int max_iterations = 100;  ///< IPOPT's iteration limit per solve
  double tolerance = 1e-8;   ///< IPOPT's tol per solve
  bool warm_start = true;    ///< each solve starts from the last plan shifted by one period
  SourceLocation where;      ///< the `mpc` entry
};
struct SceneController {
  bool present = false;
  double period = 0;
  SourceLocation where;                ///< the table
  SourceLocation period_where;         ///< its period
  NumberExpression period_expression;  ///< the period written through the parameters
  std::vector<SceneControllerState> states;
  std::vector<SceneControllerLaw> inputs;  ///< in file order
  std::vector<SceneControllerLaw> update;  ///< one per state, in the states' order
  SceneMpc mpc;  ///< sets every input of [inputs] that is not a feedback law (no `inputs`, `states` beside it)
};

/// A number of [optimize] as written: a number, or a constant expression of the parameters
/// ("L/2", as [initial] and [simulate] take), which value_at() evaluates at the parameter values
/// of the time (a value set since the file was read counts, as for [initial]).
struct SceneNumber {
  double value = 0;          ///< at the file's parameter values
  std::string text;          ///< the expression as written; "" for a number
  std::string what;          ///< its name in messages ("t_end's low bound")
  bool infinite_ok = false;  ///< ±inf is allowed (an open side of a bound)
  SourceLocation where;
  /// The value at `parameters` (Scene::parameter_values_by_name()); InputError at `where` when the
  /// expression fails there or the value is not a finite number (±inf when `infinite_ok`).
  double value_at(const std::map<std::string, double>& parameters) const;
};

/// A coordinate's derivative of some order, an input or a named quantity of [outputs], by its
/// scene name ("x", "x'", "u1", "speed").
struct PathQuantity {
  enum class Kind { coordinate, input, output } kind = Kind::coordinate;
  int index = 0;  ///< coordinate, input or output index
  int order = 0;  ///< derivative order (0 for an input)
  std::string name;
};

/// `x = 0.0` or `x = [low, high]` of [optimize.initial] and [optimize.final], `u1 = [-5.0, 5.0]`
/// of [optimize.bounds].
struct SceneOptimizeEntry {
  PathQuantity quantity;
  SourceLocation where;        ///< the name
  SourceLocation value_where;  ///< the value (the array of a range)
  bool range = false;          ///< [low, high]; else low and high are the one value
  SceneNumber low, high;
  std::string what;  ///< the entry in messages ("x in [optimize.initial]")
};

/// [optimize] (docs/scenes.md, "Optimal motions"): the problem of `nhc optimize` as written; the
/// numbers and the objective's parameters take their values when it is solved
/// (optimize::read_settings).
struct SceneOptimize {
  bool present = false;
  SourceLocation where;                ///< the [optimize] header
  std::optional<GiNaC::ex> objective;  ///< of t, q, q', …, the inputs and the parameters; none: the Lagrangian
  SourceLocation objective_where;
  GiNaC::ex final_cost = 0;  ///< of t and the final state
  SourceLocation final_cost_where;
  std::vector<SceneNumber> t_end;  ///< none: [simulate]'s t_end; one: a fixed horizon; two: [low, high]
  SourceLocation t_end_where;      ///< the entry (else the table's header)
  std::optional<int> intervals;
  std::optional<ModelKind> model;
  SourceLocation model_where;  ///< the `model` entry (else the table's header)
  std::vector<SceneOptimizeEntry> initial, final, bounds;
};

/// A [parameters] entry written through other parameters (`Ja = "mw*r^2/2"`): not a parameter of
/// the equations but an expression of them, substituted where its name appears, so that it
/// follows every change of the parameters it uses (--set, ensembles, sweeps).
struct DerivedParameter {
  std::string name;
  GiNaC::ex value;  ///< of the parameters (JetSpace::parameter symbols) and numbers
};

/// The system: what the equations and the generated model are made from (docs/architecture.md,
/// "The scene's three parts"). Every field is listed in SceneSystem::source_text()'s check.
struct SceneSystemFields {
  std::string name;         ///< valid C++ identifier, used for file names
  std::string source_path;  ///< file the scene came from ("" when built in code)
  /// Definitions were kept as named intermediates (SceneOptions), so the expressions below
  /// name them.
  bool keep_definitions = false;
  std::shared_ptr<JetSpace> jet;
  std::vector<DerivedParameter> derived_parameters;  ///< each after those it uses
  GiNaC::ex lagrangian;                              ///< L(t, q, q')
  SourceLocation lagrangian_where;                   ///< where the scene file writes L (refusals point there)
  std::vector<GiNaC::ex> constraints;                ///< f^α(t, q, …, q^(m_α)) = 0
  std::vector<std::string> constraint_texts;
  std::vector<int> dependent;     ///< coordinate indices d_1..d_g (suslov); may be empty
  std::vector<ModelKind> models;  ///< requested models, default all four
  /// Where the scene's `models` key lists each model (empty when it has no `models` key: then
  /// every model is requested, none by name).
  std::map<ModelKind, SourceLocation> models_where;
  SourceLocation constraints_where;  ///< the `constraints` key's value (none: line 0)
  /// Generalized non-conservative forces Q_i(t, q, q') of [forces], one per coordinate (0 when
  /// not given); every model adds Q_i to its residual R_i (docs/forces.md).
  std::vector<GiNaC::ex> forces;
  /// [inputs], in file order (JetSpace::inputs() order): the symbols, the feedback laws and the
  /// default signals, which the generated model computes (what a run feeds instead is the run's).
  std::vector<SceneInput> inputs;
  std::vector<SceneQuantity> invariants;  ///< [invariants]: I(t, q, q', …, λ), computed by the model
  SceneReference reference;               ///< [reference]: computed by the model
  /// The Euler angles the scene's omega() and omega_body() met, in any of its expressions
  /// (value.hpp), each once, in the order met: the model monitors where they are singular, to name
  /// the angle when a run fails near there (docs/quaternions.md).
  std::vector<EulerChain> euler_chains;
};

/// The system with the text it was read from. The text stands for the system only as read:
/// source_text() compares every field with what it was when the text was recorded, so code that
/// changes an expression of a parsed scene leaves a system without text — which the scene cache
/// (nhc/jit/scene_cache.hpp) never keys — and nothing has to be cleared by hand.
class SceneSystem : public SceneSystemFields {
 public:
  /// The text parse_scene() read (SceneBuilder's too), while every field is still what it was
  /// read as; "" for a system assembled in code or changed since (a field assigned, an
  /// expression replaced by another that is not GiNaC::ex::is_equal to it).
  const std::string& source_text() const;
  /// Records `text` as what the system, as it is now, was read from (parse_scene() does).
  void set_source_text(std::string text);

  int coordinate_count() const { return jet->coordinate_count(); }
  int constraint_count() const { return static_cast<int>(constraints.size()); }
  /// The scene file as a place for messages about the scene as a whole.
  SourceLocation file_location() const { return {source_path.empty() ? "scene" : source_path, 0, 0}; }

 private:
  struct Reading;  // the text, and every field as it was read (scene_system.cpp)
  std::shared_ptr<const Reading> reading_;
};

/// The experiment: what starts, steers and stops a run of the system. Values here are keyed
/// one by one where a product depends on them (the parameter values are the generated model's
/// defaults), never through the text.
struct SceneExperiment {
  std::vector<double> parameter_values;  ///< in JetSpace parameter order
  InitialData initial;
  SimulateSettings simulate;
  std::vector<SceneEvent> events;      ///< [events], in file order
  std::vector<SceneContact> contacts;  ///< [contacts], in file order
  /// [controller]: a sampled controller, evaluated by the run between integrations (not in the
  /// generated model); `present` false when the scene has none.
  SceneController controller;
  /// [optimize]: the optimal-motion problem; `present` false when the scene has none.
  SceneOptimize optimize;
};

/// The presentation: what a run shows of the motion.
struct ScenePresentation {
  std::vector<SceneQuantity> outputs;  ///< [outputs], in file order
  /// [visual], in file order: what `nhc animate` draws.
  std::vector<SceneVisual> visuals;
};

struct Scene : SceneSystem, SceneExperiment, ScenePresentation {
  /// "FILE:LINE:COLUMN: warning: …" lines (a definition never used); load_scene prints them.
  std::vector<std::string> warnings;

  /// Parameter symbol → value, for numeric evaluation.
  GiNaC::exmap parameter_substitution() const;
  /// Input symbol → its default signal's value at time t (parameters at their values): the
  /// inputs at the points where nhc evaluates equations itself (the consistent initial point,
  /// an operating point of `nhc linearize`). Throws MathError naming the input where the signal
  /// is not a finite number there.
  GiNaC::exmap input_substitution(double t) const;
  /// Every parameter's value by name, those computed from others included.
  std::map<std::string, double> parameter_values_by_name() const;
  /// The parameter `name` computed from others, or null.
  const DerivedParameter* derived_parameter(const std::string& name) const;
};

/// The value of e at `values` as a finite double, or nullopt (not a number, complex, infinite).
std::optional<double> finite_value(const GiNaC::ex& e, const GiNaC::exmap& values);

/// How a scene is read.
struct SceneOptions {
  /// Each scalar definition (each entry of a vector or matrix one) stays a named intermediate
  /// (nhc/expr/intermediate.hpp) in the expressions that use it, instead of being substituted.
  /// The default; `false` is the fully substituted form (`nhc derive --expand`).
  bool keep_definitions = true;
};

/// Reads and validates a scene file. Every problem is an InputError naming FILE:LINE:COLUMN;
/// warnings are printed on stderr.
Scene load_scene(const std::string& path, const SceneOptions& options = {});

/// Same, from text already in memory; `path` is only used in messages. Warnings stay in
/// Scene::warnings.
Scene parse_scene(const std::string& text, const std::string& path, const SceneOptions& options = {});

/// Recomputes the [initial] values written as expressions from the scene's current parameter
/// values (after `--set`, `--at` or a sweep changed one), so that a bicycle's wheel rates
/// `v/rR` follow its speed v. Values given as numbers, or overridden since, are left alone.
void reevaluate_initial_expressions(Scene& scene);

/// The scene text without the tables of the experiment and the presentation ([initial],
/// [simulate], [optimize], [events], [contacts], [outputs], [visual]), re-serialized: the
/// system's text, what the equations and the generated header are made from, so that the scene
/// cache finds one header for every start, tolerance and display (nhc/jit/scene_cache.hpp).
/// `text` must be a scene parse_scene() accepted; text that is not TOML comes back unchanged.
std::string equations_source(const std::string& text);

/// The scene text of a switched model (docs/contacts.md, "Sliding"): the constraints `removed`
/// (0-based) dropped, `added_forces` (coordinate name -> expression) added to [forces], the
/// multipliers' entries of [initial] dropped (the remaining ones are renumbered), and the tables
/// that name multipliers or steer the run ([contacts], [events], [outputs], [invariants],
/// [reference], [visual], [optimize]) removed. The text as given when it is not TOML.
std::string switched_source(const std::string& text, const std::set<int>& removed,
                            const std::map<std::string, std::string>& added_forces);

/// True for C++ keywords and alternative tokens (and, or, …), which a scene may not use as names.
bool is_cpp_keyword(const std::string& name);
/// [A-Za-z_][A-Za-z0-9_]* and not a C++ keyword.
bool is_valid_identifier(const std::string& name);

}  // namespace nhc
