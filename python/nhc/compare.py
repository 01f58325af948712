"""nhc.compare: one scene under several models, the same run each (`nhc compare` without its report)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, Iterable

if TYPE_CHECKING:
    from .model import Run
    from .scene import Scene


def compare(scene: Scene, models: Iterable[str], **simulate: Any) -> Dict[str, Run]:
    """Each of `models` built and run from the same initial data: ``{model: Run}``.

    :param scene: the scene (:class:`nhc.Scene`).
    :param models: model names: ``["chetaev", "vakonomic"]``.
    :param simulate: the keyword arguments of :meth:`nhc.Model.simulate` (t_end, rtol, atol,
        outputs, output_times), the same for every model.
    :raises nhc.Error: a model that fails raises its error."""
    return {model: scene.build(model).simulate(**simulate) for model in models}
