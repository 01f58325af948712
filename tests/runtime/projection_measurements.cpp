// Drift, steps and time of the projection methods on the index-1 pendulum (docs/projection.md).
// Run: build-runtime/tests/runtime/nhc_projection_measurements
#include <cstdio>
#include <chrono>
#include "synthetic_models.hpp"
#include "appell_hamel_fixture.hpp"
using namespace nhc::runtime;
int main() {
  const nhc_model_table table = synthetic::pendulum::table();
  const Model model = Model::from_table(&table);
  for (double rtol : {1e-6, 1e-8}) {
    for (double tend : {20.0, 200.0}) {
      struct Cfg {
        const char* name;
        ProjectionMethod m;
        double thr;
      };
      for (Cfg c :
           {Cfg{"none", ProjectionMethod::none, 0}, Cfg{"restart 0.1", ProjectionMethod::restart, 0.1},
            Cfg{"restart 1", ProjectionMethod::restart, 1.0}, Cfg{"restart 10", ProjectionMethod::restart, 10.0},
            Cfg{"in_place 0", ProjectionMethod::in_place, 0.0}, Cfg{"in_place 0.1", ProjectionMethod::in_place, 0.1},
            Cfg{"in_place 1", ProjectionMethod::in_place, 1.0}}) {
        IntegratorOptions o;
        o.rtol = rtol;
        o.atol = rtol * 1e-2;
        o.projection = c.m;
        o.projection_threshold = c.thr;
        InitialState s;
        s.y = {1, 0, 0, 0, 0};
        s.given = {true, true, false, false, false};
        auto t0 = std::chrono::steady_clock::now();
        RunResult r = simulate(model, {}, s, output_times(0, tend, 2000), o);
        double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        DriftReport d = measure_drift(model, model.default_parameters(), r.samples);
        std::printf("rtol %.0e t_end %5.0f %-13s drift %9.2e energy %9.2e steps %7ld res %8ld proj %6ld  %.3f s %s\n",
                    rtol, tend, c.name, d.max_hidden, d.invariant_drift[0], r.statistics.steps,
                    r.statistics.residual_evaluations, r.statistics.projections, sec,
                    r.failure ? r.failure->what() : "");
      }
    }
  }
}
