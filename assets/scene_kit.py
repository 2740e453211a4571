"""Scene content for the demo, the tests and the benchmarks, made by code: terrains, low-poly prototypes and
exemplars of collection instances. Nothing here is an opaque binary: anyone can regenerate every asset."""

import math
import pathlib

import bmesh
import bpy
import numpy as np
from mathutils import Matrix
from worldpaint.bridge import engine

CATEGORY_COLLECTIONS = {"tree": "Tree", "rock": "Rock", "grass": "Grass"}
TERRAIN_COLOR = (0.55, 0.50, 0.36, 1.0)
COLORS = {"Tree": (0.05, 0.45, 0.08, 1.0), "Rock": (0.50, 0.48, 0.45, 1.0), "Grass": (0.70, 0.85, 0.20, 1.0)}


def mesh_object(name, co, faces):
    """A mesh object from vertex coordinates (N, 3) and faces (F, k), written with foreach_set."""
    co = np.asarray(co, dtype=np.float32)
    faces = np.asarray(faces, dtype=np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(co))
    mesh.vertices.foreach_set("co", co.ravel())
    k = faces.shape[1]
    mesh.loops.add(faces.size)
    mesh.loops.foreach_set("vertex_index", faces.ravel())
    mesh.polygons.add(len(faces))
    mesh.polygons.foreach_set("loop_start", np.arange(0, faces.size, k, dtype=np.int32))
    mesh.update()
    mesh.validate()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def grid_terrain(name, origin, cell, heights):
    """A grid mesh terrain: heights (ny, nx) sampled at origin + (i, j) * cell."""
    heights = np.asarray(heights, dtype=np.float64)
    ny, nx = heights.shape
    x, y = np.meshgrid(origin[0] + cell * np.arange(nx), origin[1] + cell * np.arange(ny))
    co = np.column_stack([x.ravel(), y.ravel(), heights.ravel()])
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1))
    v0 = (j * nx + i).ravel()
    quads = np.column_stack([v0, v0 + 1, v0 + 1 + nx, v0 + nx])
    obj = mesh_object(name, co, quads)
    obj.data.materials.append(_material("Terrain", TERRAIN_COLOR))
    return obj


def engine_terrain_object(name, terrain):
    """A grid mesh of an engine Terrain (e.g. from the exemplar generators)."""
    g = terrain.grid()
    return grid_terrain(name, g["origin"], g["cell"], g["heights"])


def hills_terrain(name="Hills", size=120.0, cell=1.0, seed=5):
    return engine_terrain_object(name, engine.exemplar_demo_terrain(size, cell, seed))


def irregular_terrain(name="Irregular", size=100.0, n=60, seed=3):
    """A non-grid triangle mesh: jittered vertices, triangles of varying shape, smooth analytic heights."""
    rng = np.random.default_rng(seed)
    step = size / (n - 1)
    x, y = np.meshgrid(np.arange(n) * step, np.arange(n) * step)
    jitter = rng.uniform(-0.3, 0.3, size=(2, n, n)) * step
    inner = np.zeros((n, n), bool)
    inner[1:-1, 1:-1] = True
    x = x + np.where(inner, jitter[0], 0.0)
    y = y + np.where(inner, jitter[1], 0.0)
    z = 4.0 * np.sin(x / 17.0) * np.cos(y / 23.0) + 0.05 * x
    co = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    v0 = (j * n + i).ravel()
    flip = rng.random(len(v0)) < 0.5
    t1 = np.where(flip[:, None], np.column_stack([v0, v0 + 1, v0 + n]), np.column_stack([v0, v0 + 1, v0 + n + 1]))
    t2 = np.where(
        flip[:, None], np.column_stack([v0 + 1, v0 + n + 1, v0 + n]), np.column_stack([v0, v0 + n + 1, v0 + n])
    )
    return mesh_object(name, co, np.concatenate([t1, t2]))


def _material(name, rgba):
    mat = bpy.data.materials.new(name)
    mat.diffuse_color = rgba
    return mat


def _bmesh_object(name, bm, rgba):
    mesh = bpy.data.meshes.new(name + "Mesh")
    bm.to_mesh(mesh)
    bm.free()
    mesh.materials.append(_material(name, rgba))
    return bpy.data.objects.new(name + "Proto", mesh)


def prototypes():
    """Collections Tree, Rock and Grass, each holding one tiny low-poly mesh, excluded from the view layer."""
    scene = bpy.context.scene
    parent = bpy.data.collections.new("Prototypes")
    scene.collection.children.link(parent)
    built = {}
    for name in ("Tree", "Rock", "Grass"):
        bm = bmesh.new()
        if name == "Tree":
            bmesh.ops.create_cone(bm, cap_ends=True, segments=6, radius1=1.5, radius2=0.0, depth=5.0,
                                  matrix=Matrix.Translation((0.0, 0.0, 2.5)))
        elif name == "Rock":
            bmesh.ops.create_icosphere(bm, subdivisions=1, radius=0.8)
        else:
            bmesh.ops.create_cone(bm, cap_ends=False, segments=3, radius1=0.3, radius2=0.0, depth=0.5,
                                  matrix=Matrix.Translation((0.0, 0.0, 0.25)))
        collection = bpy.data.collections.new(name)
        parent.children.link(collection)
        collection.objects.link(_bmesh_object(name, bm, COLORS[name]))
        built[name] = collection
    bpy.context.view_layer.layer_collection.children["Prototypes"].exclude = True
    return built


def collection_instances(collection_name, positions, z, rotations=None, scales=None, parent=None):
    """Collection-instance empties (hand-placed examples) at world positions (N, 2) and heights z (N)."""
    target = parent or bpy.context.scene.collection
    collection = bpy.data.collections[collection_name]
    made = []
    for k, (p, h) in enumerate(zip(positions, z, strict=True)):
        obj = bpy.data.objects.new(f"{collection_name}.ex{k:04d}", None)
        obj.instance_type = 'COLLECTION'
        obj.instance_collection = collection
        obj.location = (float(p[0]), float(p[1]), float(h))
        if rotations is not None:
            obj.rotation_euler = (0.0, 0.0, float(rotations[k]))
        if scales is not None:
            obj.scale = (float(scales[k]),) * 3
        target.objects.link(obj)
        made.append(obj)
    return made


def slope_exemplar(size=200.0, exemplar=100.0, seed=1):
    """The engine's slope scene: its terrain as a grid mesh, and its instances inside [0, exemplar]² as examples.

    Trees only on 20-35 degree slopes, rocks anywhere, grass clustered around rocks. Returns (terrain object,
    example objects, engine scene dict).
    """
    scene_data = engine.exemplar_slope_scene(size, seed)
    terrain_obj = engine_terrain_object("Terrain", scene_data["terrain"])
    prototypes()
    examples_collection = bpy.data.collections.new("Examples")
    bpy.context.scene.collection.children.link(examples_collection)
    pos = scene_data["positions"]
    inside = (pos[:, 0] < exemplar) & (pos[:, 1] < exemplar)
    examples = []
    for index, category in enumerate(scene_data["categories"]):
        mask = inside & (scene_data["category_index"] == index)
        examples += collection_instances(
            CATEGORY_COLLECTIONS[category["name"]],
            pos[mask],
            scene_data["heights"][mask],
            scene_data["rotations"][mask],
            scene_data["scales"][mask],
            parent=examples_collection,
        )
    bpy.context.scene.worldpaint.terrain = terrain_obj
    return terrain_obj, examples, scene_data


def flat_terrain(name="Flat", size=(300.0, 200.0), cell=2.0):
    """A flat grid terrain from the origin, ``size`` metres across."""
    nx, ny = int(round(size[0] / cell)) + 1, int(round(size[1] / cell)) + 1
    return grid_terrain(name, (0.0, 0.0), cell, np.zeros((ny, nx)))


def hard_core_examples(collection_name, corner, size, density, min_distance, seed):
    """Hand-placed examples on flat ground at z = 0: a hard-core arrangement in the square at ``corner``."""
    region = {"shape": "rect", "min": list(corner), "max": [corner[0] + size, corner[1] + size]}
    xy = engine.exemplar_hard_core(region, density, min_distance, seed)
    return collection_instances(collection_name, xy, np.zeros(len(xy)))


def select_only(objects):
    bpy.context.view_layer.update()
    for obj in bpy.context.scene.objects:
        obj.select_set(False)
    for obj in objects:
        obj.select_set(True)
    if objects:
        bpy.context.view_layer.objects.active = objects[0]


def top_camera(center, height, ortho_scale):
    cam = bpy.data.objects.new("TopCamera", bpy.data.cameras.new("TopCamera"))
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = ortho_scale
    cam.data.clip_end = height * 4.0
    cam.location = (center[0], center[1], height)
    cam.rotation_euler = (0.0, 0.0, 0.0)
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam
    return cam


def poly_curve(name, points, cyclic=False, collection=None):
    """A curve object of one poly spline through ``points``: (N, 2) at height 0, or (N, 3); linked to
    ``collection`` (default: the scene's)."""
    points = np.asarray(points, dtype=np.float64)
    if points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    curve = bpy.data.curves.new(name, 'CURVE')
    curve.dimensions = '3D'
    spline = curve.splines.new('POLY')
    spline.points.add(len(points) - 1)
    spline.points.foreach_set("co", np.column_stack([points, np.ones(len(points))]).ravel())
    spline.use_cyclic_u = cyclic
    obj = bpy.data.objects.new(name, curve)
    (collection or bpy.context.scene.collection).objects.link(obj)
    return obj


def evaluated_vertices(obj):
    """World XYZ (N, 3) of a mesh object's vertices as shown: shape keys and modifiers applied."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    matrix = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def closed_circle_curve(name, center, radius):
    bpy.ops.curve.primitive_bezier_circle_add(radius=radius, location=(center[0], center[1], 0.0))
    obj = bpy.context.active_object
    obj.name = name
    return obj


def degrees(x):
    return math.degrees(x)


def village_height(x, y):
    """The gentle valley side the village exemplar stands on (m)."""
    return 0.06 * x + 0.03 * y + 2.0 * np.sin(np.asarray(x) / 45.0) * np.cos(np.asarray(y) / 70.0)


def village_exemplar(size=300.0, extent=(-100.0, -100.0, 900.0, 450.0), seed=1, cell=2.0, origin=(0.0, 0.0)):
    """The engine's village moved to ``origin``: its streets as a hand-drawn curve object "Roads" (curve data "road",
    one poly spline per street, on the terrain) and its houses as instances of a "House" collection, on a sloped grid
    terrain covering ``extent``. Returns (terrain object, road curve object, house objects, engine data)."""
    data = engine.exemplar_village(size, seed)
    shift = np.asarray(origin, dtype=np.float64)
    data["positions"] = data["positions"] + shift
    for path in data["paths"]:
        path["points"] = path["points"] + shift
    x0, y0, x1, y1 = extent
    nx, ny = int(round((x1 - x0) / cell)) + 1, int(round((y1 - y0) / cell)) + 1
    x, y = np.meshgrid(x0 + cell * np.arange(nx), y0 + cell * np.arange(ny))
    terrain_obj = grid_terrain("Terrain", (x0, y0), cell, village_height(x, y))

    curve = bpy.data.curves.new("road", 'CURVE')
    curve.dimensions = '3D'
    road_index = [c["name"] for c in data["categories"]].index("road")
    for path in data["paths"]:
        if path["category"] != road_index:
            continue
        xy = path["points"]
        spline = curve.splines.new('POLY')
        spline.points.add(len(xy) - 1)
        co = np.column_stack([xy, village_height(xy[:, 0], xy[:, 1]), np.ones(len(xy))])
        spline.points.foreach_set("co", co.ravel())
    roads = bpy.data.objects.new("Roads", curve)
    bpy.context.scene.collection.objects.link(roads)

    parent = bpy.data.collections.get("Prototypes")
    if parent is None:
        parent = bpy.data.collections.new("Prototypes")
        bpy.context.scene.collection.children.link(parent)
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0, matrix=Matrix.Translation((0.0, 0.0, 0.5)) @ Matrix.Diagonal((8, 6, 5, 1)))
    houses = bpy.data.collections.new("House")
    parent.children.link(houses)
    houses.objects.link(_bmesh_object("House", bm, (0.8, 0.4, 0.3, 1.0)))
    bpy.context.view_layer.layer_collection.children["Prototypes"].exclude = True
    mask = data["category_index"] == [c["name"] for c in data["categories"]].index("house")
    xy = data["positions"][mask]
    house_objects = collection_instances("House", xy, village_height(xy[:, 0], xy[:, 1]), data["rotations"][mask])
    bpy.context.scene.worldpaint.terrain = terrain_obj
    return terrain_obj, roads, house_objects, data


def stone_prototypes():
    """Collections Cobble (a low hexagonal slab) and Pebble (a small one), excluded from the view layer."""
    scene = bpy.context.scene
    parent = bpy.data.collections.new("Stones")
    scene.collection.children.link(parent)
    built = {}
    for name, radius, rgba in (("Cobble", 0.45, (0.45, 0.43, 0.40, 1.0)), ("Pebble", 0.2, (0.62, 0.58, 0.52, 1.0))):
        bm = bmesh.new()
        bmesh.ops.create_cone(bm, cap_ends=True, segments=6, radius1=radius, radius2=0.85 * radius, depth=0.15,
                              matrix=Matrix.Translation((0.0, 0.0, 0.075)))
        collection = bpy.data.collections.new(name)
        parent.children.link(collection)
        collection.objects.link(_bmesh_object(name, bm, rgba))
        built[name] = collection
    bpy.context.view_layer.layer_collection.children["Stones"].exclude = True
    return built


def hexagonal_lattice(corner, rows, cols, spacing, jitter=0.03, seed=3):
    """XY (rows * cols, 2) of a hexagonal lattice from ``corner``, each point moved by up to ``jitter`` spacings."""
    rng = np.random.default_rng(seed)
    row, col = np.divmod(np.arange(rows * cols), cols)
    xy = np.column_stack([col + 0.5 * (row % 2), row * math.sqrt(3.0) / 2.0]) * spacing + np.asarray(corner)
    return xy + rng.uniform(-jitter, jitter, xy.shape) * spacing


def cobble_reference(corner=(10.0, 10.0), rows=7, cols=7, spacing=1.0):
    """A hand-placed reference of cobbles on a hexagonal lattice at z = 0; returns the example objects."""
    stone_prototypes()
    xy = hexagonal_lattice(corner, rows, cols, spacing)
    return collection_instances("Cobble", xy, np.zeros(len(xy)))


def vine_prototype():
    """A collection Vine holding one small low-poly vine (a green cone on a post), excluded from the view layer."""
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, segments=5, radius1=0.35, radius2=0.1, depth=1.4,
                          matrix=Matrix.Translation((0.0, 0.0, 0.7)))
    collection = bpy.data.collections.new("Vine")
    bpy.context.scene.collection.children.link(collection)
    collection.objects.link(_bmesh_object("Vine", bm, (0.22, 0.45, 0.12, 1.0)))
    bpy.context.view_layer.layer_collection.children["Vine"].exclude = True
    return collection


def vineyard_reference(corner, rows=5, cols=8, along=1.2, between=3.0, shear=0.35, seed=4):
    """A hand-planted block of vines at z = 0: ``rows`` rows along X, ``along`` metres apart in a row and ``between``
    metres between rows, each row shifted by ``shear`` of a step so the triangulation has one way to fall."""
    vine_prototype()
    rng = np.random.default_rng(seed)
    row, col = np.divmod(np.arange(rows * cols), cols)
    xy = np.column_stack([(col + shear * row) * along, row * between]) + np.asarray(corner)
    xy += rng.uniform(-0.03, 0.03, xy.shape)
    return collection_instances("Vine", xy, np.zeros(len(xy)))


def segmented_tree(name="Column tree", sides=8, radius=0.4, height=1.5, crown=(1.6, 3.0)):
    """A low-poly tree of three parts sharing rings of vertices: a lower and an upper trunk segment and a conical
    crown, its bottom capped. The integer face attribute ``part`` labels them 0, 1 and 2."""
    a = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    ring = np.column_stack([np.cos(a), np.sin(a)])
    co = [np.column_stack([radius * ring, np.full(sides, z)]) for z in (0.0, height, 2 * height)]
    co.append(np.column_stack([crown[0] * ring, np.full(sides, 2 * height)]))
    co.append(np.array([[0.0, 0.0, 2 * height + crown[1]]]))
    co = np.vstack(co)
    faces, parts = [], []
    for level in (0, 1):
        for k in range(sides):
            j = (k + 1) % sides
            b, t = level * sides, (level + 1) * sides
            faces.append((b + k, b + j, t + j, t + k))
            parts.append(level)
    top, brim, apex = 2 * sides, 3 * sides, 4 * sides
    for k in range(sides):
        j = (k + 1) % sides
        faces.append((top + k, top + j, brim + j, brim + k))  # the crown's underside, from the trunk's top ring
        faces.append((brim + k, brim + j, apex))
        parts += [2, 2]
    faces.append(tuple(range(sides - 1, -1, -1)))  # the bottom cap
    parts.append(0)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(co.tolist(), [], faces)
    mesh.update()
    attr = mesh.attributes.new("part", 'INT', 'FACE')
    attr.data.foreach_set("value", np.asarray(parts, dtype=np.int32))
    mesh.materials.append(_material(name, COLORS["Tree"]))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def tilt_ring(obj, above, angle, axis):
    """Turns the vertices of a part's mesh above height ``above`` about the horizontal ``axis`` ('X' or 'Y') through
    (0, 0, above), as a solid: the part's top ring leans and what stands on it follows."""
    c, s = math.cos(angle), math.sin(angle)
    for v in obj.data.vertices:
        if v.co.z > above - 1e-3:
            z = v.co.z - above
            if axis == 'X':
                v.co.y, v.co.z = v.co.y * c - z * s, above + v.co.y * s + z * c
            else:
                v.co.x, v.co.z = v.co.x * c - z * s, above + v.co.x * s + z * c


def edited_part(tree, label, name):
    """A copy of a decomposed part's piece in its collection, as Shift+D makes one."""
    collection = tree.worldpaint_variety.parts.children[f"{tree.name} part {label}"]
    piece = collection["wp_part"]
    copy = piece.copy()
    copy.data = piece.data.copy()
    copy.name = name
    collection.objects.link(copy)
    return copy


def tree_variants(tree, height=1.5):
    """Edited copies of a decomposed ``segmented_tree``'s parts: both trunk segments leaning two ways, the crown
    taller, shorter and narrower (4 x 3 x 3 = 36 trees)."""
    for label, above in ((0, height), (1, 2 * height)):
        for k, (angle, axis) in enumerate(((0.15, 'X'), (-0.12, 'Y'))):
            tilt_ring(edited_part(tree, label, f"lean {label}.{k}"), above, angle, axis)
    for name, dz in (("tall", 1.2), ("short", -0.8)):
        crown = edited_part(tree, 2, f"crown {name}")
        apex = max(crown.data.vertices, key=lambda v: v.co.z)
        apex.co.z += dz
    narrow = edited_part(tree, 2, "crown narrow")
    for v in narrow.data.vertices:
        if math.hypot(v.co.x, v.co.y) > 0.5:
            v.co.x, v.co.y = 0.7 * v.co.x, 0.7 * v.co.y


def parts_object(name, co, faces, parts, rgba):
    """A mesh object of polygons ``faces`` (lists of vertex indices) with the integer face attribute ``part``."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(np.asarray(co).tolist(), [], [tuple(int(v) for v in f) for f in faces])
    mesh.update()
    attr = mesh.attributes.new("part", 'INT', 'FACE')
    attr.data.foreach_set("value", np.asarray(parts, dtype=np.int32))
    mesh.materials.append(_material(name, rgba))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def ring_of_parts(name="Ring", sections=16, corners=6):
    """A ring of four parts (the seed's fully cyclic graph, Fig. 11, as a torus): ``sections`` sections of ``corners``
    vertices around a circle of radius 2 m (tube radius 0.5 m), parts of four segments each (``part`` 0-3); each
    part meets the next in one section."""
    a = 2.0 * np.pi * np.arange(sections) / sections
    b = 2.0 * np.pi * np.arange(corners) / corners
    radius = 2.0 + 0.5 * np.cos(b)
    co = np.stack([np.outer(np.cos(a), radius), np.outer(np.sin(a), radius),
                   np.tile(0.5 * np.sin(b), (sections, 1))], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(sections), np.arange(corners), indexing='ij')
    at = lambda i, j: (i % sections) * corners + j % corners  # noqa: E731
    faces = np.stack([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)], axis=-1).reshape(-1, 4)
    return parts_object(name, co, faces, (i // 4).ravel(), COLORS["Rock"])


def cactus(name="Cactus"):
    """A low-poly cactus of seven parts as a tree: an 8-sided trunk of 9 rings 0.8 m apart (``part`` 0 lower, 1
    middle, 2 top with its dome), two arms out of quad holes in the lower and middle trunk (3 and 5), each going out
    then up through an elbow, their upper rings a part of their own (4 and 6, the tips). Returns the object and, per
    arm, its rings 1 to 6 as (6, 4, 3) positions (1-2 out, 3 the elbow, 4 where the tip starts, 6 the top)."""
    sides = 8
    a = 2.0 * np.pi * (np.arange(sides) + 0.5) / sides
    co = [(0.5 * math.cos(t), 0.5 * math.sin(t), 0.8 * r) for r in range(9) for t in a] + [(0.0, 0.0, 7.0)]
    apex = len(co) - 1
    at = lambda r, s: r * sides + s % sides  # noqa: E731
    holes = ((1, 0, 3), (4, 4, 5))
    faces, parts = [], []
    for seg in range(8):
        for s in range(sides):
            if (seg, s) not in {(h[0], h[1]) for h in holes}:
                faces.append((at(seg, s), at(seg, s + 1), at(seg + 1, s + 1), at(seg + 1, s)))
                parts.append(0 if seg <= 2 else 1 if seg <= 5 else 2)
    faces.append(tuple(at(0, s) for s in reversed(range(sides))))
    parts.append(0)
    for s in range(sides):
        faces.append((at(8, s), at(8, s + 1), apex))
        parts.append(2)
    arms = []
    for seg, s, label in holes:
        hole = (at(seg, s), at(seg, s + 1), at(seg + 1, s + 1), at(seg + 1, s))
        corners = np.array([co[v] for v in hole])
        centre = corners.mean(axis=0)
        out = np.array([centre[0], centre[1], 0.0]) / math.hypot(centre[0], centre[1])
        z = np.array([0.0, 0.0, 1.0])
        across = np.cross(z, out)
        offsets = [((p - centre) @ across, (p - centre) @ z) for p in corners]
        previous, rings = hole, []
        for k in range(1, 7):
            if k <= 2:
                c, up, shrink = centre + out * 0.45 * k, z, 0.8
            elif k == 3:
                c, up, shrink = centre + out * 1.3 + z * 0.35, (z - out) / math.sqrt(2.0), 0.7
            else:
                c, up, shrink = centre + out * 1.5 + z * (0.9 + 0.55 * (k - 4)), -out, 0.6
            ring = [c + (across * x + up * y * 0.45) * shrink for x, y in offsets]
            rings.append(ring)
            index = list(range(len(co), len(co) + 4))
            co.extend(tuple(p) for p in ring)
            for e in range(4):
                faces.append((previous[e], previous[(e + 1) % 4], index[(e + 1) % 4], index[e]))
                parts.append(label if k <= 4 else label + 1)
            previous = index
        faces.append(tuple(previous))
        parts.append(label + 1)
        arms.append(np.array(rings))
    return parts_object(name, co, faces, parts, COLORS["Tree"]), arms


BIRCH = pathlib.Path(__file__).resolve().parent / "birch.obj"


def import_birch():
    """The variety test tree (``birch.obj``, made by ``birch.py``) through Blender's OBJ importer: one mesh object
    'Birch' of six material slots, one per component (trunk, branch_a, branch_b, crown, clump_a, clump_b)."""
    assert bpy.ops.wm.obj_import(filepath=str(BIRCH), forward_axis='Y', up_axis='Z') == {'FINISHED'}
    return bpy.data.objects["Birch"]


def in_edit_mode(obj, edit):
    """Runs ``edit(bm)`` on ``obj``'s mesh in Edit Mode, as a user moving or deleting there, and leaves it."""
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode='EDIT')
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.index_update()
    bm.faces.index_update()
    edit(bm)
    bmesh.update_edit_mesh(obj.data)
    bpy.ops.object.mode_set(mode='OBJECT')


def apply_modifier(obj, kind, vertices, **settings):
    """Adds a modifier of ``kind`` limited to a vertex group of ``vertices`` (indices), sets ``settings`` on it and
    applies it (Object > Apply)."""
    group = obj.vertex_groups.new(name=kind.lower())
    group.add([int(v) for v in vertices], 1.0, 'REPLACE')
    modifier = obj.modifiers.new(kind.title(), kind)
    modifier.vertex_group = group.name
    for key, value in settings.items():
        setattr(modifier, key, value)
    with bpy.context.temp_override(object=obj, active_object=obj):
        assert bpy.ops.object.modifier_apply(modifier=modifier.name) == {'FINISHED'}


def lattice_shear(obj, vertices, amount):
    """A 2x2x2 Lattice around ``obj`` whose top corners are moved ``amount`` metres along X, applied to ``vertices``:
    every vertex moves along X in proportion to its height in the box (a shear)."""
    co = np.array([v.co for v in obj.data.vertices])
    lo, hi = co.min(axis=0), co.max(axis=0)
    lattice = bpy.data.objects.new(f"{obj.name} lattice", bpy.data.lattices.new(f"{obj.name} lattice"))
    bpy.context.scene.collection.objects.link(lattice)
    lattice.location, lattice.scale = tuple((lo + hi) / 2), tuple(hi - lo)
    for point in lattice.data.points:
        if point.co.z > 0.0:
            point.co_deform.x += amount / (hi - lo)[0]
    apply_modifier(obj, 'LATTICE', vertices, object=lattice)
    bpy.data.objects.remove(lattice)


def open_boundary(mesh):
    """bool (N,): the vertices on edges of one face (a part's connecting regions)."""
    uses = np.zeros(len(mesh.edges), dtype=np.int64)
    edge = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("edge_index", edge)
    np.add.at(uses, edge, 1)
    ends = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", ends)
    out = np.zeros(len(mesh.vertices), dtype=bool)
    out[ends.reshape(-1, 2)[uses == 1].ravel()] = True
    return out


def birch_variants(tree):
    """Two edited copies of each part of a decomposed ``import_birch`` tree, made with Blender's tools (3^6 = 729
    trees): the trunk's base flared in Edit Mode and its lowest rings twisted by a Simple Deform; each branch tilted
    from its first ring in Edit Mode (its leaf mass follows) and kinked at its middle ring by a Lattice; every other
    leaf clump of each leaf mass deleted in Edit Mode, and each mass sheared by a Lattice. Connecting rings stay."""
    trunk = edited_part(tree, 0, "Trunk flared")
    foot = Matrix.Translation(-np.array([v.co for v in trunk.data.vertices if abs(v.co.z) < 1e-4]).mean(axis=0))
    in_edit_mode(trunk, lambda bm: bmesh.ops.scale(bm, vec=(1.35, 1.35, 1.0), space=foot,
                                                   verts=[v for v in bm.verts if abs(v.co.z) < 1e-4]))
    trunk = edited_part(tree, 0, "Trunk twisted")
    apply_modifier(trunk, 'SIMPLE_DEFORM', [v.index for v in trunk.data.vertices if 0.5 < v.co.z < 2.5],
                   deform_method='TWIST', deform_axis='Z', angle=math.radians(10.0))
    for label, name, angle in ((1, "a", 8.0), (2, "b", -8.0)):
        branch = edited_part(tree, label, f"Branch {name} tilted")
        co = np.array([v.co for v in branch.data.vertices])
        ring = np.nonzero(open_boundary(branch.data))[0]
        base = ring[np.argsort(np.hypot(co[ring, 0], co[ring, 1]))[:len(ring) // 2]]
        root, tip = co[base].mean(axis=0), co[np.setdiff1d(ring, base)].mean(axis=0)
        axis = tip - root
        rings = np.rint((co - root) @ axis / (axis @ axis) * 5.0).astype(int)
        pivot = co[rings == 1].mean(axis=0)
        across = np.cross(axis, (0.0, 0.0, 1.0))
        turn = Matrix.Rotation(math.radians(angle), 3, across / np.linalg.norm(across))
        in_edit_mode(branch, lambda bm, rings=rings, turn=turn, pivot=pivot: bmesh.ops.rotate(
            bm, cent=pivot, matrix=turn, verts=[v for v in bm.verts if rings[v.index] >= 2]))
        kinked = edited_part(tree, label, f"Branch {name} kinked")
        lattice = bpy.data.objects.new("Kink lattice", bpy.data.lattices.new("Kink lattice"))
        bpy.context.scene.collection.objects.link(lattice)
        lattice.location, lattice.scale = tuple(co.mean(axis=0)), tuple(co.max(axis=0) - co.min(axis=0) + 0.1)
        for point in lattice.data.points:
            point.co_deform.z += 0.08 / lattice.scale.z
        apply_modifier(kinked, 'LATTICE', np.nonzero(rings == 3)[0], object=lattice)
        bpy.data.objects.remove(lattice)
    for label, name, first, shear in ((3, "Crown", 1, 0.3), (4, "Clump a", 0, 0.25), (5, "Clump b", 0, -0.25)):
        thinned = edited_part(tree, label, f"{name} thinned")
        doomed = set(leaf_clumps(thinned.data)[first::2].ravel().tolist())
        in_edit_mode(thinned, lambda bm, doomed=doomed: bmesh.ops.delete(
            bm, geom=[f for f in bm.faces if f.index in doomed], context='FACES'))
        sheared = edited_part(tree, label, f"{name} sheared")
        lattice_shear(sheared, np.nonzero(~open_boundary(sheared.data))[0], shear)


def leaf_clumps(mesh):
    """int (clumps, 20): the faces of each closed clump of a leaf mass (the face islands that do not touch its open
    ring), in the order of their first face."""
    totals = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", totals)
    corners = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    parent = np.arange(len(mesh.vertices))

    def root(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    face_of = np.repeat(np.arange(len(totals)), totals)
    first = {}
    for f, v in zip(face_of.tolist(), corners.tolist(), strict=True):
        parent[root(v)] = root(first.setdefault(f, v))
    island = np.array([root(v) for v in corners[np.cumsum(totals) - totals]])
    ring = {root(v) for v in np.nonzero(open_boundary(mesh))[0].tolist()}
    groups = {}
    for f, r in enumerate(island.tolist()):
        if r not in ring:
            groups.setdefault(r, []).append(f)
    return np.array([groups[r] for r in sorted(groups, key=lambda r: groups[r][0])])


# --- the sketch scene (thesis ch. 5) -------------------------------------------------------------------------------

SKETCH_CELL = 4.0
SKETCH_N = 129


def hills_height(x, y):
    """A near ridge, a middle ridge and a hill in front of it, with metre-scale detail."""
    ridge = np.maximum(18.0 * np.exp(-((y - 100.0) / 12.0) ** 2), 40.0 * np.exp(-((y - 260.0) / 18.0) ** 2))
    hill = 45.0 * np.exp(-((x - 256.0) ** 2 + (y - 130.0) ** 2) / 15.0**2)
    detail = 0.8 * np.sin(0.31 * x) * np.cos(0.27 * y) + 0.5 * np.sin(0.53 * x + 0.41 * y)
    return np.maximum(ridge, hill) + detail


def sketch_scene(name="Terrain", camera_name="Camera"):
    """The terrain and a level camera at its south edge looking north (60° wide, 3:2)."""
    x, y = np.meshgrid(SKETCH_CELL * np.arange(SKETCH_N), SKETCH_CELL * np.arange(SKETCH_N))
    terrain = grid_terrain(name, (0.0, 0.0), SKETCH_CELL, hills_height(x, y))
    terrain.color = (0.55, 0.5, 0.38, 1.0)
    scene = bpy.context.scene
    scene.worldpaint.terrain = terrain
    scene.render.resolution_x, scene.render.resolution_y = 1200, 800
    camera = bpy.data.objects.new(camera_name, bpy.data.cameras.new(camera_name))
    camera.data.sensor_fit = 'HORIZONTAL'
    camera.data.angle = math.radians(60.0)
    camera.data.clip_end = 2000.0
    camera.location = (256.0, -60.0, 12.0)
    camera.rotation_euler = (math.radians(90.0), 0.0, 0.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    return terrain, camera


def three_strokes():
    """A front mountain, one behind it to the right and one behind it to the left, each of the back ones ending on
    the front one's slope (two T-junctions)."""
    def front(x):
        return 0.62 + 0.09 * np.exp(-((x - 0.38) / 0.12) ** 2)

    xs = np.linspace(0.18, 0.62, 30)
    right = np.linspace(0.52, 0.9, 30)
    left = np.linspace(0.06, 0.27, 20)
    return [
        np.column_stack([xs, front(xs)]),
        np.column_stack([right, front(0.52) + 0.1 * np.sin(np.pi * (right - 0.52) / 0.5) + 0.01 * (right - 0.52)]),
        np.column_stack([left, front(0.27) + 0.08 * np.sin(np.pi * (0.27 - left) / 0.3)]),
    ]


def draw_strokes(strokes):
    """Strokes (camera-frame points, 0-1) as if drawn with the Sketch Silhouettes tool."""
    settings = bpy.context.scene.worldpaint.sketch
    settings.strokes.clear()
    for stroke in strokes:
        item = settings.strokes.add()
        for x, y in stroke:
            item.points.add().co = (x, y)
