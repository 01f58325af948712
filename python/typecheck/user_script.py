"""A small user script, fully annotated: python:mypy checks it with mypy --strict against the
package's annotations and the compiled module's stubs (nhc/_nhc.pyi, py.typed)."""
from typing import Dict, List

import numpy as np
import numpy.typing as npt

import nhc


def final_positions(path: str, speeds: List[float]) -> Dict[float, float]:
    scene: nhc.Scene = nhc.Scene.load(path, set={"m": 1.0})
    model: nhc.Model = scene.build("chetaev")
    out: Dict[float, float] = {}
    for v in speeds:
        run: nhc.Run = model.simulate(t_end=2.0, rtol=1e-9, output_times=np.linspace(0, 2, 5))
        x: npt.NDArray[np.float64] = run["x"]
        out[v] = float(x[-1])
    return out


def stability(path: str) -> str:
    lin: nhc.Linearization = nhc.Scene.load(path).linearize("chetaev", at={"phi'": 0.0})
    return str(lin.verdict)


try:
    print(final_positions("knife.toml", [1.0, 2.0]), stability("knife.toml"))
except nhc.SceneError as error:
    print(error.file, error.line, error.column)
except nhc.MathError as error:
    print(error.t)
