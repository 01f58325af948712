// A model from a generated namespace and the same model loaded from a shared object agree.
#include <catch2/catch.hpp>

#include <string>

#include "appell_hamel_fixture.hpp"

using namespace nhc::runtime;

TEST_CASE("a model compiled in and the same model loaded with dlopen integrate identically", "[runtime]") {
  const ah_test::AppellHamel ah;
  const Model direct = ah_test::model();
  const Model loaded = Model::load(NHC_TEST_MODULE);
  CHECK(loaded.scene_name() == "appell_hamel");
  CHECK(loaded.model_name() == "chetaev");
  CHECK(loaded.n_states() == 7);
  CHECK(loaded.n_singular() == 1);
  CHECK(loaded.state_index(3, 0) == 6);
  CHECK(loaded.variable_name(3) == "lambda1");
  CHECK(loaded.residual_name(3) == "D f1");
  IntegratorOptions o;
  const auto times = output_times(0.0, 0.2, 20);
  const RunResult a = simulate(direct, {}, ah.initial(), times, o);
  const RunResult b = simulate(loaded, {}, ah.initial(), times, o);
  REQUIRE_FALSE(a.failure.has_value());
  REQUIRE_FALSE(b.failure.has_value());
  REQUIRE(a.samples.size() == b.samples.size());
  for (size_t k = 0; k < a.samples.size(); ++k) CHECK(a.samples[k].y == b.samples[k].y);
  // The library stays loaded while a copy of the model lives.
  Model copy = loaded;
  CHECK(copy.table().residual != nullptr);
}

TEST_CASE("loading failures are ModelErrors that say why", "[runtime]") {
  try {
    Model::load("/nonexistent/model.so");
    FAIL("no exception");
  } catch (const nhc::base::ModelError& e) {
    CHECK(std::string(e.what()).find("/nonexistent/model.so") != std::string::npos);
  }
  nhc_model_table bad = *nhc_gen::appell_hamel_chetaev::model_table();
  bad.abi_version = 7;
  CHECK_THROWS_AS(Model::from_table(&bad), nhc::base::ModelError);
  bad.abi_version = 1;
  bad.residual = nullptr;
  CHECK_THROWS_WITH(Model::from_table(&bad), Catch::Contains("no residual"));
  // An ABI-1 table: the runtime must not read the fields of the additions.
  nhc_model_table v1 = *nhc_gen::appell_hamel_chetaev::model_table();
  v1.abi_version = 1;
  const Model old = Model::from_table(&v1);
  CHECK(old.n_singular() == 0);
  CHECK(old.residual_name(0) == "residual 0");
}
