"""nhc.compare: one scene under several models, the same run each (`nhc compare` without its report)."""


def compare(scene, models, **simulate):
    """{model: Run} for each of `models` (built and simulated with the same keyword arguments:
    t_end, rtol, atol, outputs, output_times). A model that fails raises its nhc.Error."""
    return {model: scene.build(model).simulate(**simulate) for model in models}
