#pragma once
/// \file model_kind.hpp
/// \brief The dynamical models nhc derives (docs/models.md, "The four models"), their names, and
/// the one rule that picks a scene's default model. Every command, the CMake function
/// nhc_add_model() (through `nhc generate`) and the benchmark take the names and the default
/// from here.

#include <optional>
#include <string>
#include <vector>

namespace nhc {

struct Scene;

enum class ModelKind { vakonomic, chetaev, holder, suslov };

inline constexpr ModelKind kAllModels[] = {ModelKind::vakonomic, ModelKind::chetaev, ModelKind::holder,
                                           ModelKind::suslov};

std::string to_string(ModelKind model);
std::optional<ModelKind> parse_model_kind(const std::string& name);
/// "vakonomic", "chetaev", "holder", "suslov": the values a `--model` flag accepts.
std::vector<std::string> model_names();
/// "vakonomic, chetaev, holder, suslov": the names in messages about an unknown model.
std::string model_name_list();

/// The scene's [simulate] model, else chetaev when the scene lists it, else the scene's first
/// model (chetaev when it lists none).
ModelKind default_model(const Scene& scene);
/// `name` when not empty (a model name; InputError-free: the flag was checked against
/// model_names()), else default_model(scene).
ModelKind model_or_default(const Scene& scene, const std::string& name);

}  // namespace nhc
