// The printed and generated forms of a scene depend on the scene only, not on what the process
// derived before (docs/intermediates.md, "The same equations whatever ran before"): the text, the
// LaTeX (with the multiplier-free form) and the header of a scene derived after other scenes, and
// from several threads, are byte-identical to those of its first derivation.
#include <catch2/catch.hpp>

#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/scene/scene.hpp"

namespace {

const std::vector<std::string> kScenes = {"chaplygin_sleigh", "rolling_disk",     "appell_hamel",
                                          "knife_edge",       "wheeled_pendulum", "rattleback"};

struct Forms {
  std::string text, latex, header;
};

Forms forms(const std::string& name) {
  const nhc::Scene scene = nhc::load_scene(std::string(NHC_SOURCE_DIR) + "/examples/" + name + ".toml");
  std::vector<nhc::DerivedModel> models{nhc::derive_model(scene, nhc::ModelKind::chetaev)};
  models.front().reduced =
      std::make_shared<const nhc::ReducedForm>(nhc::reduce_to_independent_speeds(scene, models.front()));
  Forms f;
  std::ostringstream text, latex;
  nhc::write_derivation_text(text, scene, models);
  nhc::write_derivation_latex(latex, scene, models);
  f.text = text.str();
  f.latex = latex.str();
  const nhc::Index1System system = nhc::reduce_to_index1(scene, models.front());
  nhc::HeaderOptions options;
  f.header = nhc::generate_header(scene, system, options).text;
  return f;
}

/// The forms that differ from `expected`, named.
std::vector<std::string> differences(const std::string& name, const Forms& got, const Forms& expected) {
  std::vector<std::string> out;
  if (got.text != expected.text) out.push_back(name + ": text");
  if (got.latex != expected.latex) out.push_back(name + ": latex");
  if (got.header != expected.header) out.push_back(name + ": header");
  return out;
}

}  // namespace

TEST_CASE("a scene derived after other scenes prints and generates the same", "[derive][determinism]") {
  std::vector<Forms> first;
  for (const std::string& name : kScenes) first.push_back(forms(name));
  std::vector<std::string> problems;
  for (std::size_t round = 1; round < kScenes.size(); ++round)
    for (std::size_t k = 0; k < kScenes.size(); ++k) {  // a different history before each scene
      const std::size_t s = (k + round) % kScenes.size();
      for (const std::string& p : differences(kScenes[s], forms(kScenes[s]), first[s])) problems.push_back(p);
    }
  INFO(problems.size() << " forms differ");
  CHECK(problems.empty());
}

TEST_CASE("scenes derived from several threads print and generate the same", "[derive][determinism]") {
  std::vector<Forms> first;
  for (const std::string& name : kScenes) first.push_back(forms(name));
  std::mutex symbolic;  // GiNaC: one thread at a time (long_work.hpp, SymbolicLock)
  std::vector<std::string> problems;
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t k = 0; k < kScenes.size(); ++k) {
        const std::size_t s = (k * (t + 1) + t) % kScenes.size();
        std::lock_guard<std::mutex> lock(symbolic);
        for (const std::string& p : differences(kScenes[s], forms(kScenes[s]), first[s])) problems.push_back(p);
      }
    });
  for (std::thread& thread : threads) thread.join();
  INFO(problems.size() << " forms differ");
  CHECK(problems.empty());
}
