"""The stub of the compiled engine (``worldpaint_engine/_engine.pyi``) says what the module is: the same names, the same
parameters (names, kinds and defaults, as pyo3 gives them in ``__text_signature__``), the same exception hierarchy,
and result dicts with the keys its ``TypedDict``s declare. The type check of the add-on is only as true as this stub.

A ``**options: Unpack[SomeOptions]`` of the stub (PEP 692) stands for the keys of its ``TypedDict``: keyword-only
parameters of the compiled function, with the default None where their type admits None and some default where it
does not (none for a ``Required`` key), unless the compiled function takes ``**options`` itself.
"""

import ast
import inspect
import json
import pathlib
import re
from importlib import resources

import numpy as np
import pytest
from worldpaint_engine import _engine

STUB = pathlib.Path(__file__).resolve().parents[1] / "rust/worldpaint-py/python/worldpaint_engine/_engine.pyi"
TREE = ast.parse(STUB.read_text(encoding="utf-8"))
TOP = {node.name: node for node in TREE.body if isinstance(node, ast.FunctionDef | ast.ClassDef)}


def declared_all():
    (node,) = [n for n in TREE.body if isinstance(n, ast.Assign) and n.targets[0].id == "__all__"]
    return ast.literal_eval(node.value)


def is_typed_dict(node):
    return isinstance(node, ast.ClassDef) and any(
        (isinstance(b, ast.Name) and (b.id == "TypedDict" or is_typed_dict(TOP.get(b.id)))) for b in node.bases)


def type_only_names():
    """The names the stub declares for type checkers only: TypedDicts and aliases."""
    names = {name for name, node in TOP.items() if is_typed_dict(node)}
    for node in TREE.body:
        if isinstance(node, ast.AnnAssign) and ast.unparse(node.annotation) == "TypeAlias":
            names.add(node.target.id)
        elif isinstance(node, ast.Assign) and isinstance(node.value, ast.Call) and \
                ast.unparse(node.value.func) == "TypedDict":
            names.add(node.targets[0].id)
    return names


def typed_dict_declarations(name):
    """{key: (annotation text, whether the key is required)} of a TypedDict of the stub, with those of its bases (the
    ``total`` of a class holds for the keys it declares)."""
    node = TOP[name]
    declared = {}
    for base in node.bases:
        if isinstance(base, ast.Name) and base.id in TOP:
            declared |= typed_dict_declarations(base.id)
    total = not any(k.arg == "total" and ast.literal_eval(k.value) is False for k in node.keywords)
    for n in node.body:
        if isinstance(n, ast.AnnAssign):
            annotation = ast.unparse(n.annotation)
            required = annotation.startswith("Required[") or (total and not annotation.startswith("NotRequired["))
            declared[n.target.id] = annotation, required
    return declared


def typed_dict_fields(name):
    """{key: annotation text} of a TypedDict of the stub, with those of its bases."""
    return {key: annotation for key, (annotation, _) in typed_dict_declarations(name).items()}


def typed_dict_keys(name):
    return set(typed_dict_fields(name))


# the array annotations of the stub and the dtype each stands for
DTYPES = {"Float64Array": np.float64, "Int32Array": np.int32, "Int64Array": np.int64, "NDArray[np.float32]": np.float32,
          "NDArray[np.uint8]": np.uint8, "NDArray[np.uint32]": np.uint32, "NDArray[np.bool_]": np.bool_}


def check(result, name, optional=()):
    """``result`` has the keys of the stub's TypedDict ``name`` (those in ``optional`` may be absent, no other key may
    be there), and its arrays the dtypes the stub gives them."""
    fields = typed_dict_fields(name)
    assert set(result) <= set(fields) and set(fields) - set(optional) <= set(result), name
    for key, value in result.items():
        annotation = fields[key]
        if annotation.startswith("NotRequired["):
            annotation = annotation.removeprefix("NotRequired[").removesuffix("]")
        dtype = DTYPES.get(annotation.removesuffix(" | None"))
        if dtype is not None and value is not None:
            assert isinstance(value, np.ndarray), f"{name}[{key!r}] is a {type(value).__name__}, not an array"
            assert value.dtype == dtype, f"{name}[{key!r}]: {value.dtype}, not {np.dtype(dtype)}"


# the default of a keyword a stub's TypedDict stands for, where its type does not admit None: any default at all
SOME_DEFAULT = "<some default>"


def unpacked(arg):
    """The TypedDict a ``**kw: Unpack[TD]`` of the stub unpacks, or None."""
    annotation = arg.annotation
    if isinstance(annotation, ast.Subscript) and ast.unparse(annotation.value) == "Unpack":
        return ast.unparse(annotation.slice)
    return None


def keywords_of(typed_dict):
    """(name, KEYWORD_ONLY, default) of each key of a stub's TypedDict unpacked as keywords: no default for a
    required key, else None where the key's type admits None and ``SOME_DEFAULT`` where it does not."""
    out = []
    for key, (annotation, required) in typed_dict_declarations(typed_dict).items():
        annotation = re.sub(r"^(Not)?Required\[(.*)\]$", r"\2", annotation)
        if required:
            default = inspect.Parameter.empty
        elif annotation == "None" or annotation.endswith("| None"):
            default = None
        else:
            default = SOME_DEFAULT
        out.append((key, inspect.Parameter.KEYWORD_ONLY, default))
    return out


def stub_parameters(function, drop_first=False, runtime=()):
    """(name, kind, default) of each parameter of a function of the stub; a ``**kw: Unpack[TD]`` is the TypedDict's
    keys (``keywords_of``) unless the compiled function's parameters ``runtime`` take ``**kw`` too."""
    a = function.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + a.defaults
    for arg, default in zip(positional, defaults, strict=True):
        kind = inspect.Parameter.POSITIONAL_ONLY if arg in a.posonlyargs else inspect.Parameter.POSITIONAL_OR_KEYWORD
        out.append((arg.arg, kind, ast.literal_eval(default) if default else inspect.Parameter.empty))
    if a.vararg:
        out.append((a.vararg.arg, inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.empty))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults, strict=True):
        out.append((arg.arg, inspect.Parameter.KEYWORD_ONLY,
                    ast.literal_eval(default) if default else inspect.Parameter.empty))
    if a.kwarg and unpacked(a.kwarg) and (a.kwarg.arg, inspect.Parameter.VAR_KEYWORD) not in {p[:2] for p in runtime}:
        out += keywords_of(unpacked(a.kwarg))
    elif a.kwarg:
        out.append((a.kwarg.arg, inspect.Parameter.VAR_KEYWORD, inspect.Parameter.empty))
    return out[1:] if drop_first else out


def runtime_parameters(obj, drop_self=False):
    """(name, kind, default) of each parameter of a compiled function, from the signature pyo3 gives it."""
    assert obj.__text_signature__, f"{obj!r} has no text signature"
    params = list(inspect.signature(obj).parameters.values())
    if drop_self:
        params = params[1:]
    return [(p.name, p.kind, p.default) for p in params]


def assert_same_parameters(stub, runtime, what=""):
    """The stub's parameters are the compiled function's: the positional ones in order, the keyword-only ones in any
    order (a caller names them); a default ``SOME_DEFAULT`` of the stub's stands for any default of the function's."""
    keyword = (inspect.Parameter.KEYWORD_ONLY, inspect.Parameter.VAR_KEYWORD)
    some = {name for name, _, default in stub if default == SOME_DEFAULT}
    assert [p for p in stub if p[1] not in keyword] == [p for p in runtime if p[1] not in keyword], what
    assert sorted(p for p in stub if p[1] in keyword) == sorted(
        (name, kind, SOME_DEFAULT if name in some and default is not inspect.Parameter.empty else default)
        for name, kind, default in runtime if kind in keyword), what


def test_the_stub_declares_every_name_the_module_exports_and_no_other():
    exported = {name for name in dir(_engine) if not name.startswith("_")} | {"__version__"}
    assert set(declared_all()) == exported
    defined = set(TOP) | {n.target.id for n in TREE.body if isinstance(n, ast.AnnAssign)} | {
        t.id for n in TREE.body if isinstance(n, ast.Assign) for t in n.targets}
    assert set(declared_all()) <= defined, "names in __all__ the stub does not define"
    type_only = type_only_names()
    assert not type_only & exported, "a name the module exports is declared as a type only"
    runtime_looking = {name for name in defined - type_only if not name.startswith("_")}
    assert runtime_looking <= set(declared_all()), f"not in __all__: {sorted(runtime_looking - set(declared_all()))}"


@pytest.mark.parametrize("name", sorted(n for n in declared_all() if isinstance(TOP.get(n), ast.FunctionDef)))
def test_each_function_takes_the_parameters_the_stub_gives_it(name):
    runtime = runtime_parameters(getattr(_engine, name))
    assert_same_parameters(stub_parameters(TOP[name], runtime=runtime), runtime)


@pytest.mark.parametrize("name", ["Scene", "Stroke", "Terrain"])
def test_each_class_has_the_constructor_and_methods_the_stub_gives_it(name):
    cls = getattr(_engine, name)
    methods = {n.name: n for n in TOP[name].body if isinstance(n, ast.FunctionDef)}
    runtime = {m for m in vars(cls) if m not in ("__doc__", "__module__")}
    assert set(methods) == runtime
    constructor = runtime_parameters(cls)
    assert_same_parameters(stub_parameters(methods["__new__"], drop_first=True, runtime=constructor), constructor)
    for method, node in methods.items():
        if method == "__new__":
            continue
        static = any(ast.unparse(d) == "staticmethod" for d in node.decorator_list)
        parameters = runtime_parameters(getattr(cls, method), drop_self=not static)
        assert_same_parameters(stub_parameters(node, drop_first=not static, runtime=parameters), parameters, method)


def test_the_exceptions_derive_as_the_stub_says():
    for name in ("WorldPaintError", "InputError", "FileFormatError", "NothingToLearn", "Cancelled", "InternalError"):
        bases = tuple(ast.unparse(b) for b in TOP[name].bases)
        assert tuple(b.__name__ for b in getattr(_engine, name).__bases__) == bases, name


def test_the_constants_are_as_declared():
    assert set(_engine.LIMITS) == typed_dict_keys("Limits")
    assert all(isinstance(v, int) for v in _engine.LIMITS.values())
    assert isinstance(_engine.PALETTE_FORMAT_VERSION, int) and isinstance(_engine.__version__, str)


SQUARE = {"shape": "rect", "min": [0.0, 0.0], "max": [40.0, 40.0]}


def test_the_painting_results_carry_the_keys_and_dtypes_their_typed_dicts_declare():
    """Colors, the painting tools, regions and terrains."""
    pts = _engine.exemplar_hard_core(SQUARE, 0.04, 2.5, 1)
    scene = _engine.Scene(None, [{"name": "tree"}], pts, np.zeros(len(pts), np.int32))
    color = _engine.learn_color(scene, SQUARE, "trees")
    summary = _engine.color_summary(color)
    check(summary, "ColorSummaryDict")
    check(summary["categories"][0], "ColorCategoryDict")
    check(_engine.compare(color, color), "FidelityDict")
    empty = _engine.Scene(None, [{"name": "tree"}], np.zeros((0, 2)), np.zeros(0, np.int32))
    check(_engine.synthesize(empty, color, SQUARE, 1), "SynthesisDict")
    pasted = _engine.paste(scene, color, SQUARE, 2)
    check(pasted, "PastedDict", optional=("fidelity_error", "pattern"))
    check(pasted["fidelity"], "FidelityDict")
    check(pasted["categories"][0], "CategoryDict")
    check(_engine.clear_region(scene, SQUARE), "EditDict")
    check(_engine.move_region(scene, color, {"shape": "circle", "center": [20.0, 20.0], "radius": 8.0}, (5.0, 0.0)),
          "MovedDict")
    stretched = _engine.stretch_region(scene, {"shape": "rect", "min": [10.0, 10.0], "max": [30.0, 30.0]}, "east",
                                       5.0, color)
    check(stretched, "StretchedDict")
    check(stretched["region"], "RectRegion")
    check(_engine.fidelity(color, None, 1, width=64, height=32), "FidelityViewDict")
    village = _engine.exemplar_village(80.0, 3)
    check(village, "VillageSceneDict")
    check(village["paths"][0], "Polyline")
    terrain = _engine.exemplar_demo_terrain(40.0, 2.0, 7)
    check(terrain.grid(), "TerrainGrid")
    square = np.array([[5.0, 5.0], [30.0, 5.0], [30.0, 30.0], [5.0, 30.0]])
    check(_engine.fill_polygons([square], 5.0, terrain), "FilledPolygonsDict")
    check(_engine.exemplar_slope_scene(60.0, 1), "SlopeSceneDict")


def test_the_other_results_carry_the_keys_and_dtypes_their_typed_dicts_declare():
    """Arrangements, worlds, model and texture variety, villages, roads, waterfalls and sketches, on small inputs."""
    pts = _engine.exemplar_hard_core(SQUARE, 0.04, 2.5, 1)
    color = _engine.learn_color(_engine.Scene(None, [{"name": "tree"}], pts, np.zeros(len(pts), np.int32)), SQUARE, "t")
    plan = _engine.world_plan(color, (0.0, 0.0), (100.0, 100.0))
    check(plan, "WorldPlanDict")
    column, row, _phase, _after = plan["tiles"][0]
    tile, _border, _counts = _engine.world_tile(color, plan, column, row, [], 1)
    check(_engine.read_world_tile(tile), "WorldTileDict")

    lattice = np.array([[x + 0.5 * (y % 2), 0.866 * y] for y in range(12) for x in range(12)]) * 2.0
    cobbles = [{"name": "cobble", "kind": "arrangement"}]
    reference = _engine.Scene(None, cobbles, lattice, np.zeros(len(lattice), np.int32))
    arrangement = _engine.learn_arrangement(reference, {"shape": "rect", "min": [-0.5, -0.5], "max": [24.5, 19.5]}, "c")
    summary = _engine.arrangement_summary(arrangement)
    check(summary, "ArrangementSummaryDict")
    check(summary["lattice"], "LatticeDict")
    empty = _engine.Scene(None, cobbles, np.zeros((0, 2)), np.zeros(0, np.int32))
    pasted = _engine.paste(empty, arrangement, {"shape": "rect", "min": [0.0, 0.0], "max": [20.0, 20.0]}, 1)
    check(pasted, "PastedDict", optional=("fidelity_error",))
    check(pasted["pattern"], "PatternFidelityDict")

    # two quads side by side, one component each
    model = {"vertices": np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], np.float64),
             "loop_totals": np.array([4, 4], np.int64), "corners": np.array([0, 1, 4, 3, 1, 2, 5, 4], np.int64),
             "uvs": np.array([[0, 0], [0.5, 0], [0.5, 1], [0, 1], [0.5, 0], [1, 0], [1, 1], [0.5, 1]], np.float64)}
    labels = np.array([0, 1], np.int64)
    decomposition = _engine.decompose_model(model, labels)
    check(decomposition, "DecompositionDict")
    check(decomposition["components"][1], "Model")
    raised = dict(decomposition["components"][1])
    raised["vertices"] = raised["vertices"] + np.where(raised["vertices"][:, :1] > 1.5, [0.0, 0.0, 0.1], 0.0)
    variants = _engine.generate_variants(model, labels, [[], [raised]], 2, 1)
    check(variants, "VariantsDict")
    check(variants["memory"], "MemoryDict")
    check(variants["models"][0], "Model")
    base = np.zeros((8, 8, 4), np.uint8)
    painted = base.copy()
    painted[1:3, 1:3, 0] = 200
    texture = _engine.texture_variety(model, base, [painted], 2)
    check(texture, "TextureVarietyDict")
    check(texture["components"][0], "TextureComponentDict")

    terrain = _engine.exemplar_demo_terrain(200.0, 2.0, 7)
    (x0, y0), (x1, y1) = terrain.bbox()
    middle = np.array([[x0 + 100.0, y0 + 100.0]])
    scenario = json.dumps({"events": json.loads(_engine.scenario_presets())["presets"]["farming_hamlet"]["events"]})
    village = _engine.generate_village(terrain, {"shape": "rect", "min": [x0, y0], "max": [x1, y1]}, scenario, 1)
    check(village, "VillageDict")
    for key, name in (("seeds", "VillageSeedsDict"), ("report", "VillageReportDict")):
        check(village[key], name)
    check(village["roads"][0], "RoadDict")
    check(village["houses"][0], "HouseDict")
    road = np.array([[x0 + 20.0, y0 + 100.0], [x1 - 20.0, y0 + 100.0]])
    check(_engine.embed_roads(terrain, [road], middle), "RoadEmbeddingDict")
    stream = np.array([[x0 + 100.0, y0 + 40.0, 0.0], [x0 + 100.0, y0 + 160.0, 0.0]])
    stream[:, 2] = terrain.heights_at(stream[:, :2])
    waterfall = _engine.build_waterfall(terrain, [{"kind": "contact", "points": stream}], middle)
    check(waterfall, "WaterfallDict")
    check(waterfall["water"], "WaterMeshDict")
    check(waterfall["segments"][0], "WaterfallSegmentDict")
    check(waterfall["report"], "WaterfallReportDict")
    check(waterfall["report"]["nodes"], "WaterfallNodesDict")
    camera = {"eye": [x0 + 100.0, y0 - 150.0, 80.0], "forward": [0.0, 1.0, -0.2], "up": [0.0, 0.2, 1.0],
              "frame_min": [-0.5, -0.3], "frame_max": [0.5, 0.3]}
    sketch = _engine.apply_sketch(terrain, camera, [np.array([[0.1, 0.6], [0.5, 0.7], [0.9, 0.6]])], middle,
                                  max_change=1e6)
    check(sketch, "SketchDict")
    check(sketch["seconds"], "SketchSecondsDict")


def test_the_keyword_dicts_name_the_keywords_the_functions_take():
    """The TypedDicts the facade unpacks into a call (``**options``) hold the keywords the function takes, and the
    surroundings of a village the ones the engine reads (it names them when it refuses another)."""
    def keywords(function, *excluded):
        params = inspect.signature(function).parameters.values()
        return {p.name for p in params if p.kind == inspect.Parameter.KEYWORD_ONLY} - set(excluded)

    assert typed_dict_keys("ArrangementChanges") == keywords(_engine.arrangement_edited)
    assert typed_dict_keys("WaterfallOptions") == keywords(_engine.build_waterfall)
    assert typed_dict_keys("VillageSetting") - typed_dict_keys("Surroundings") == keywords(
        _engine.generate_village, "progress")
    assert typed_dict_keys("InterestSetting") - typed_dict_keys("Surroundings") == keywords(_engine.village_interest)
    scene = inspect.signature(_engine.Scene).parameters
    assert typed_dict_keys("SceneColumns") | typed_dict_keys("SceneStructures") == set(scene) - {"terrain"}
    terrain = _engine.exemplar_demo_terrain(40.0, 2.0, 7)
    (x0, y0), (x1, y1) = terrain.bbox()
    with pytest.raises(_engine.InputError, match=r"the surroundings are ([a-z_, ]+)\)") as refused:
        _engine.village_interest(terrain, {"shape": "rect", "min": [x0, y0], "max": [x1, y1]}, np.zeros((1, 2)),
                                 "hamlet", "house", unknown=1.0)
    named = re.search(r"the surroundings are ([a-z_, ]+)\)", str(refused.value)).group(1)
    assert set(named.split(", ")) == typed_dict_keys("Surroundings")


def test_the_installed_package_ships_the_stub_and_says_it_is_typed():
    package = resources.files("worldpaint_engine")
    assert package.joinpath("_engine.pyi").is_file() and package.joinpath("py.typed").is_file()
