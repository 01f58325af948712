"""Every public name of nhc has a docstring that help() shows, and every parameter of a public
function or method is described in it (":param NAME:")."""
import inspect

import nhc


def public_callables():
    for name in nhc.__all__:
        obj = getattr(nhc, name)
        yield name, obj
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            for member, value in vars(obj).items():
                if not member.startswith("_") or member in ("__getitem__", "__contains__", "__len__"):
                    yield f"{name}.{member}", value


def test_every_public_name_has_a_docstring():
    missing = []
    for name, obj in public_callables():
        target = obj.fget if isinstance(obj, property) else getattr(obj, "__func__", obj)
        if not (inspect.getdoc(target) or "").strip():
            missing.append(name)
    assert not missing, f"no docstring: {missing}"


def test_every_parameter_is_described():
    undocumented = []
    for name, obj in public_callables():
        function = getattr(obj, "__func__", obj)
        if isinstance(obj, property) or inspect.isclass(obj) or not callable(function):
            continue
        doc = inspect.getdoc(function) or ""
        for parameter in inspect.signature(function).parameters.values():
            if parameter.name in ("self", "cls") or name.endswith(("__getitem__", "__contains__", "__len__")):
                continue
            if f":param {parameter.name}:" not in doc:
                undocumented.append(f"{name}({parameter.name})")
    assert not undocumented, f"parameters without :param: {undocumented}"


def test_help_shows_the_parameters():
    text = inspect.getdoc(nhc.Model.simulate)
    # Not given: the scene's [simulate] value (docs/python.md).
    assert inspect.signature(nhc.Model.simulate).parameters["t_end"].default is None
    for parameter in ("t_end", "rtol", "atol", "outputs", "inputs", "sensitivity"):
        assert f":param {parameter}:" in text
    assert "path" in inspect.signature(nhc.Scene.load).parameters


def test_help_text_names_the_parameters():
    """What help() prints (pydoc's plain text): the signature and each parameter's description."""
    import pydoc
    load = pydoc.render_doc(nhc.Scene.load, renderer=pydoc.plaintext)
    simulate = pydoc.render_doc(nhc.Model.simulate, renderer=pydoc.plaintext)
    for parameter in ("path", "set", "expand"):
        assert f"{parameter}:" in load.split("\n", 3)[2] and f":param {parameter}:" in load
    for parameter in ("t_end", "rtol", "atol", "outputs", "output_times", "inputs", "max_steps",
                      "sensitivity", "integrator", "step"):
        assert f"{parameter}:" in simulate.split("\n", 3)[2] and f":param {parameter}:" in simulate


def test_the_python_reference_lists_every_public_name():
    """docs/python-api.md (autodoc) has a directive for each name of nhc.__all__."""
    import re
    from conftest import SOURCE
    page = (SOURCE / "docs" / "python-api.md").read_text(encoding="utf-8")
    documented = set(re.findall(r"^\.\. auto(?:class|function|exception):: nhc\.(\w+)", page, re.M))
    assert set(nhc.__all__) - documented == set(), f"not on docs/python-api.md: {set(nhc.__all__) - documented}"
