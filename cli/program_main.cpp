// What every nhc program does around its commands (program_main.hpp).
// Exit codes: 0 ok, 1 internal error (a bug: please report), 2 bad input, 3 numerical or
// mathematical failure, 4 environment (file system, compiler, loader, cache).
#include "program_main.hpp"

#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "command_programs.hpp"
#include "exit_codes.hpp"
#include "failure_report.hpp"
#include "fixed_address_layout.hpp"
#include "flag_rules.hpp"
#include "interrupt.hpp"
#include "work_watchdog.hpp"
#include "nhc/errors.hpp"

namespace {

/// Out of memory before main (the static objects of the libraries and of CLI11 allocate): an
/// environment failure in words, exit 4, instead of std::terminate's abort. Installed by the
/// first static initializer of the program (init_priority 101 runs before the others).
[[noreturn]] void terminate_in_words() {
  if (std::exception_ptr failure = std::current_exception()) {
    try {
      std::rethrow_exception(failure);
    } catch (const std::bad_alloc&) {
      static const char message[] =
          "nhc: error: out of memory while starting: free memory or raise the limit (ulimit -v)\n";
      (void)!write(2, message, sizeof message - 1);
      _exit(nhc::cli::kExitEnvironment);
    } catch (...) {
    }
  }
  std::abort();
}

struct TerminateInWords {
  TerminateInWords() { std::set_terminate(terminate_in_words); }
};
__attribute__((init_priority(101))) const TerminateInWords terminate_in_words_installed;

int run_command_line(int argc, char** argv, std::initializer_list<nhc::cli::CommandAdder> adders, bool list_external) {
  // An interrupted run removes its temporary files and exits 130 (interrupt.hpp).
  nhc::cli::install_interrupt_handlers();
  CLI::App app{
      "nhc, the nonholonomic compiler: derives, analyses, generates and integrates the "
      "equations of motion of systems with high-order nonholonomic constraints"};
  app.set_version_flag("--version", std::string("nhc ") + NHC_VERSION);
  app.require_subcommand(1);

  std::vector<std::pair<CLI::App*, nhc::cli::CommandRunner>> commands;
  auto add = [&](nhc::cli::CommandRunner (*adder)(CLI::App&)) {
    nhc::cli::CommandRunner run = adder(app);
    commands.emplace_back(app.get_subcommands({}).back(), std::move(run));
  };
  for (nhc::cli::CommandAdder adder : adders) add(adder);
  // The commands of the other programs, listed by `--help` (nhc-main starts their program
  // before parsing: start_command_program).
  if (list_external)
    for (const nhc::cli::CommandProgram& entry : nhc::cli::kCommandPrograms)
      app.add_subcommand(entry.command, entry.description);

  nhc::cli::flag_rules::refuse_empty_values(app);
  if (const auto flag = nhc::cli::flag_rules::empty_inline_value(argc, argv)) {
    std::cerr << *flag << ": error: " << *flag << " " << nhc::cli::flag_rules::empty_value_message() << "\n";
    return nhc::cli::kExitBadInput;
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ValidationError& e) {
    // "--rtol: nan is not a positive number" (flag_rules.hpp) in the words of every other bad
    // flag: "--rtol: error: --rtol nan is not a positive number".
    const std::string what = e.what();
    const std::size_t colon = what.find(": ");
    if (what.rfind("-", 0) == 0 && colon != std::string::npos)
      std::cerr << what.substr(0, colon) << ": error: " << what.substr(0, colon) << " " << what.substr(colon + 2)
                << "\n";
    else std::cerr << "nhc: error: " << what << " (see nhc --help)\n";
    return nhc::cli::kExitBadInput;
  } catch (const CLI::ParseError& e) {
    std::cerr << "nhc: error: " << e.what() << " (see nhc --help)\n";
    return nhc::cli::kExitBadInput;
  }

  // Symbolic work past --work-limit ends the run with exit 2 (work_watchdog.hpp).
  nhc::cli::start_work_watchdog();
  try {
    for (auto& [sub, run] : commands)
      if (sub->parsed()) return run();
  } catch (...) {
    return nhc::cli::report_failure(std::current_exception());
  }
  return nhc::cli::kExitInternal;
}

}  // namespace

namespace nhc::cli {

namespace {
char** started_with = nullptr;
}  // namespace

char** program_arguments() { return started_with; }

int run_program(int argc, char** argv, std::initializer_list<CommandAdder> adders, bool list_external) {
  started_with = argv;
  // The same scene gives the same header in every run (fixed_address_layout.hpp).
  run_with_fixed_address_layout(argv);
  // Setting up the command line allocates too: out of memory there is exit 4 in words as well.
  try {
    return run_command_line(argc, argv, adders, list_external);
  } catch (...) {
    return report_failure(std::current_exception());
  }
}

int start_command_program(const CommandProgram& entry, char** argv) {
  const std::string directory = own_directory();
  std::string program;
  int error = ENOENT;
  if (!directory.empty()) {
    program = directory + "/" + entry.program;
    execv(program.c_str(), argv);
    error = errno;
  }
  std::cerr << "nhc: error: cannot start " << (program.empty() ? std::string(entry.program) : program)
            << ", which runs nhc " << entry.command << ": " << std::strerror(error) << "\n";
  return kExitEnvironment;
}

}  // namespace nhc::cli
