// The symbolic stages of `nhc derive` and `nhc generate` in one process, for the fuzz stage's
// replay of the corpus (tests/fuzz/replay_derive.sh, run by scripts/fuzz.sh): one scene file is
// loaded, the model it names (or the default) derived, printed as text and LaTeX, reduced to
// index 1 and generated, under the work budget asked for cooperatively (ProcessorTimeLimit,
// nhc/expr/work_stage.hpp: the Python module's stop) and without the command line's watchdog.
// What the budget cannot stop between two GiNaC calls (one call the predictions of
// work_budget.hpp let grow) therefore runs on, past the replay's per-input time limit, which fails
// the fuzz stage with the file named. Exit 0 when derived, 2 when refused (bad input or the
// budget), 3 on a mathematical failure; anything else is a bug.
// Usage: nhc_derive_replay SCENE [WORK_SECONDS]
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/long_work.hpp"
#include "nhc/scene/model_kind.hpp"
#include "nhc/scene/scene.hpp"

namespace {

class BudgetObserver final : public nhc::LongWorkObserver {
 public:
  explicit BudgetObserver(double seconds) : limit(seconds) {}
  bool stop_requested() override { return limit.exceeded(); }
  nhc::work_budget::ProcessorTimeLimit limit;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: nhc_derive_replay SCENE [WORK_SECONDS]\n";
    return 64;
  }
  const std::string path = argv[1];
  BudgetObserver observer(argc > 2 ? std::atof(argv[2]) : nhc::work_budget::kDefaultWorkSeconds);
  try {
    const nhc::ObservedWork observed(observer);
    const nhc::Scene scene = nhc::load_scene(path);
    const nhc::ModelKind kind = nhc::model_or_default(scene, "");
    const nhc::DerivedModel derived = nhc::derive_model(scene, kind);
    {
      const nhc::work_budget::Stage stage("printing the equations");
      std::ostringstream text;
      nhc::write_derivation_text(text, scene, {derived});
      nhc::write_derivation_latex(text, scene, {derived});
    }
    if (!derived.applicable) return 3;
    const nhc::Index1System system = nhc::reduce_to_index1(scene, derived);
    (void)nhc::generate_header(scene, system, nhc::HeaderOptions{});
    return 0;
  } catch (const nhc::WorkInterrupted&) {
    std::cerr << path << ": error: " << observer.limit.message("the replay's budget") << "\n";
    return 2;
  } catch (const nhc::InputError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const nhc::WorkLimitExceeded& e) {
    std::cerr << path << ": error: " << e.what() << "\n";
    return 2;
  } catch (const nhc::MathError& e) {
    std::cerr << path << ": error: " << e.what() << "\n";
    return 3;
  }
}
