// nhc plot FILE.h5 OUTCOME [-o STEM]
//
// A map of one outcome of an ensemble written by `nhc ensemble` (docs/ensemble.md): a heat map
// over a 2-D grid, a line over a 1-D grid, points for random samples; STEM.svg and STEM.png
// (gnuplot), default FILE_OUTCOME.
#include <iostream>

#include "command_programs.hpp"
#include "commands.hpp"
#include "nhc/errors.hpp"

#ifdef NHC_HAVE_ENSEMBLE
#include "nhc/ensemble.hpp"
#endif

namespace nhc::cli {

CommandRunner add_plot_command(CLI::App& app) {
  struct Options {
    std::string file, outcome, stem;
  };
  auto o = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand("plot", command_description("plot"));
  sub->add_option("FILE", o->file, "FILE.h5 written by nhc ensemble")->required();
  sub->add_option("OUTCOME", o->outcome, "t_stop, steps, seconds, final:<state>, drift:<invariant>, drift:hidden")
      ->required();
  sub->add_option("-o,--output", o->stem, "STEM: writes STEM.svg and STEM.png (default FILE_OUTCOME)");
  return [o]() {
#ifdef NHC_HAVE_ENSEMBLE
    const ensemble::EnsembleResults results = ensemble::read_results(o->file);
    const std::string stem = o->stem.empty() ? ensemble::default_plot_stem(o->file, o->outcome) : o->stem;
    for (const std::string& image : ensemble::plot_outcome(results, o->outcome, stem, "OUTCOME", {o->file}))
      std::cout << "wrote " << image << "\n";
    return kExitOk;
#else
    std::cerr << "nhc: error: nhc plot reads HDF5, which was not found when nhc was built: install Debian's "
                 "libhdf5-dev (scripts/setup.sh does) and configure again\n";
    return kExitInternal;
#endif
  };
}

}  // namespace nhc::cli
