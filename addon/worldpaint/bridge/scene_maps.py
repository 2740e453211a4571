"""Maps made in the scene, learned like the terrain's slope: a vertex group, a float or color attribute or an image
texture of the terrain, and the distance to the objects of a collection (water, rocks, roads).

A map's name says where it comes from: ``group:Moisture``, ``attribute:wetness``, ``image:noise.png``,
``distance:Water``. A color that learned one keeps the name, so Paste reads the map of the same name on the
destination's terrain (a clear error when it has none). Attributes and images are read per vertex (a color
attribute or an image by its luminance; an attribute of the faces or corners averaged at the vertices), so detail
finer than the terrain's mesh is not seen.
"""

import json

import bpy
import numpy as np

from . import WorldPaintError, engine, geometry

PREFIXES = ("group", "attribute", "image", "distance")
VERTEX_PREFIXES = ("group", "attribute", "image")
# attributes Blender keeps for itself: not maps an artist painted
SKIPPED_ATTRIBUTES = {"position", "material_index", "sharp_face", "sharp_edge"}
ATTRIBUTE_TYPES = {"FLOAT", "INT", "INT8", "BOOLEAN", "FLOAT_COLOR", "BYTE_COLOR"}
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def split(name):
    """(prefix, source) of a scene map's name; (None, name) for the terrain's own maps (slope, elevation)."""
    prefix, colon, source = name.partition(":")
    if colon and prefix in PREFIXES and source:
        return prefix, source
    return None, name


def names_in(text):
    """The map names of a comma-separated list."""
    return [name for name in (part.strip() for part in text.split(",")) if name]


def is_scene_map(name):
    return split(name)[0] is not None


def used_by(summaries):
    """The scene maps the colors (``engine.ColorSummary``) follow, in order."""
    names = [m.other for summary in summaries for m in summary.maps if m.kind == "map" and is_scene_map(m.other)]
    return list(dict.fromkeys(names))


def available(terrain_obj):
    """The maps the scene offers on ``terrain_obj``: (name, label) of its vertex groups, attributes and the images of
    its materials, and of the collections holding other objects."""
    out = [(f"group:{g.name}", f"Vertex group {g.name}") for g in terrain_obj.vertex_groups]
    for attribute in terrain_obj.data.attributes:
        if _learnable(terrain_obj.data, attribute):
            out.append((f"attribute:{attribute.name}", f"Attribute {attribute.name}"))
    images = []
    for slot in terrain_obj.material_slots:
        tree = slot.material.node_tree if slot.material is not None and slot.material.use_nodes else None
        for node in tree.nodes if tree is not None else ():
            if node.type == 'TEX_IMAGE' and node.image is not None and node.image.name not in images:
                images.append(node.image.name)
    out += [(f"image:{name}", f"Image {name}") for name in images]
    for collection in bpy.data.collections:
        if any(obj is not terrain_obj for obj in collection.all_objects):
            out.append((f"distance:{collection.name}", f"Distance to {collection.name}"))
    return out


def _learnable(mesh, attribute):
    uv_names = {uv.name for uv in mesh.uv_layers}
    return (attribute.data_type in ATTRIBUTE_TYPES and attribute.domain in {'POINT', 'EDGE', 'FACE', 'CORNER'}
            and not attribute.name.startswith(".") and attribute.name not in SKIPPED_ATTRIBUTES
            and attribute.name not in uv_names)


def vertex_values(terrain_obj, mesh, name):
    """The per-vertex values (float64, one per vertex of the evaluated ``mesh``) of a group, attribute or image map."""
    prefix, source = split(name)
    if prefix == "group":
        return _group_weights(terrain_obj, mesh, source)
    if prefix == "attribute":
        return _attribute_values(terrain_obj, mesh, source)
    return _image_values(terrain_obj, mesh, source)


def _group_weights(terrain_obj, mesh, group_name):
    group = terrain_obj.vertex_groups.get(group_name)
    if group is None:
        raise WorldPaintError(f"The terrain '{terrain_obj.name}' has no vertex group '{group_name}'")
    weights = np.zeros(len(mesh.vertices))
    index = group.index
    for vertex in mesh.vertices:
        for element in vertex.groups:
            if element.group == index:
                weights[vertex.index] = element.weight
    return weights


def _attribute_values(terrain_obj, mesh, attribute_name):
    attribute = mesh.attributes.get(attribute_name)
    if attribute is None or not _learnable(mesh, attribute):
        raise WorldPaintError(f"The terrain '{terrain_obj.name}' has no float, integer or color attribute "
                              f"'{attribute_name}'")
    n = len(attribute.data)
    if attribute.data_type in {"FLOAT_COLOR", "BYTE_COLOR"}:
        rgba = np.empty(n * 4, dtype=np.float32)
        attribute.data.foreach_get("color", rgba)
        values = rgba.reshape(-1, 4)[:, :3] @ LUMINANCE
    else:
        raw = np.empty(n, dtype=bool if attribute.data_type == "BOOLEAN" else np.float64)
        attribute.data.foreach_get("value", raw)
        values = raw.astype(np.float64)
    if attribute.domain == 'POINT':
        return values
    if attribute.domain == 'EDGE':
        ends = np.empty(len(mesh.edges) * 2, dtype=np.int64)
        mesh.edges.foreach_get("vertices", ends)
        return _mean_at_vertices(mesh, ends, np.repeat(values, 2))
    if attribute.domain == 'FACE':
        totals = np.empty(len(mesh.polygons), dtype=np.int64)
        mesh.polygons.foreach_get("loop_total", totals)
        values = np.repeat(values, totals)  # polygons' loops are consecutive, in polygon order
    return _mean_at_vertices(mesh, _loop_vertices(mesh), values)


def _image_values(terrain_obj, mesh, image_name):
    image = bpy.data.images.get(image_name)
    if image is None:
        raise WorldPaintError(f"No image '{image_name}' in the file")
    uv_layer = mesh.uv_layers.active
    if uv_layer is None:
        raise WorldPaintError(f"The terrain '{terrain_obj.name}' has no UV map to read the image '{image_name}' with")
    width, height = image.size
    if width == 0 or height == 0 or image.channels == 0:
        raise WorldPaintError(f"The image '{image_name}' has no pixels (is its file missing?)")
    pixels = np.empty(width * height * image.channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(height, width, image.channels)
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float64)
    uv_layer.data.foreach_get("uv", uv)
    uv = uv.reshape(-1, 2) % 1.0  # the image repeats, as Blender's Image Texture node does by default
    column = np.minimum((uv[:, 0] * width).astype(np.int64), width - 1)
    row = np.minimum((uv[:, 1] * height).astype(np.int64), height - 1)
    texels = pixels[row, column]
    values = texels[:, :3] @ LUMINANCE if image.channels >= 3 else texels[:, 0]
    return _mean_at_vertices(mesh, _loop_vertices(mesh), values.astype(np.float64))


def _loop_vertices(mesh):
    vertices = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", vertices)
    return vertices


def _mean_at_vertices(mesh, vertex_index, values):
    """The mean of ``values`` per vertex they belong to (``vertex_index``); 0 for a vertex none belongs to."""
    n = len(mesh.vertices)
    counts = np.bincount(vertex_index, minlength=n)
    sums = np.bincount(vertex_index, weights=values, minlength=n)
    return np.divide(sums, counts, out=np.zeros(n), where=counts > 0)


def distance_geometry(depsgraph, name, exclude):
    """World XY vertices (N, 2), edges (E, 2) and triangles (M, 3) of the objects of the collection named by a
    ``distance:`` map: meshes and curves as they are evaluated, anything else (an empty, a light) by its origin."""
    _, collection_name = split(name)
    collection = bpy.data.collections.get(collection_name)
    if collection is None:
        raise WorldPaintError(f"No collection '{collection_name}' in the file to measure the distance to")
    vertices, edges, triangles = [], [], []
    count = 0
    for obj in collection.all_objects:
        if obj in exclude:
            continue
        xy, obj_edges, obj_triangles = _object_geometry(obj, depsgraph)
        vertices.append(xy)
        edges.append(obj_edges + count)
        triangles.append(obj_triangles + count)
        count += len(xy)
    if count == 0:
        raise WorldPaintError(f"The collection '{collection_name}' has no objects to measure the distance to")
    return (np.concatenate(vertices), np.concatenate(edges).astype(np.uint32),
            np.concatenate(triangles).astype(np.uint32))


def _object_geometry(obj, depsgraph):
    origin = np.array([obj.matrix_world.translation[:2]], dtype=np.float64)
    nothing = (np.empty((0, 2), dtype=np.int64), np.empty((0, 3), dtype=np.int64))
    if obj.type not in {'MESH', 'CURVE', 'SURFACE', 'FONT', 'META'}:
        return (origin, *nothing)
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        if mesh is not None and len(mesh.vertices) > 0:
            return _mesh_geometry(obj, mesh)
        if obj.type == 'MESH' and len(obj.data.vertices) > 0:
            # a mesh shown as instances (the synthesized point clouds): its points are where they stand
            return _mesh_geometry(obj, obj.data)
        return (origin, *nothing)
    finally:
        evaluated.to_mesh_clear()


def _mesh_geometry(obj, mesh):
    xy = geometry.vertices_world(obj, mesh)[:, :2]
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int64)
    mesh.edges.foreach_get("vertices", edges)
    mesh.calc_loop_triangles()
    triangles = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    return xy, edges.reshape(-1, 2), triangles.reshape(-1, 3)


def check_names(names):
    """The scene map names, checked: an error naming one that is neither a scene map nor slope or elevation."""
    for name in names:
        if split(name)[0] is None and name not in ("slope", "elevation"):
            raise WorldPaintError(f"'{name}' is not a map: use slope, elevation or group:<vertex group>, "
                                  "attribute:<attribute>, image:<image> or distance:<collection>")
    return list(names)


# --- maps that hold one value: what they explain ------------------------------------------------------------------

MAX_SAMPLES = 1 << 20  # grid nodes read to tell whether a map holds one value in a region (a coarser stride past it)


def source_text(name, terrain_obj):
    """Where a map's values come from, in words: "the vertex group 'Moisture' of 'Terrain'"."""
    prefix, source = split(name)
    return {
        "group": f"the vertex group '{source}' of '{terrain_obj.name}'",
        "attribute": f"the attribute '{source}' of '{terrain_obj.name}'",
        "image": f"the image '{source}'",
        "distance": f"the distance to the collection '{source}'",
    }.get(prefix, f"the {name} of '{terrain_obj.name}'")


def one_value(heightfield, name, region):
    """The value map ``name`` of ``heightfield`` (an engine terrain) has at every node of its grid inside ``region``
    (an engine region), or None when it varies there or no node lies inside."""
    grid = heightfield.grid()
    (ox, oy), cell, nx, ny = grid["origin"], grid["cell"], grid["nx"], grid["ny"]
    (rx0, ry0), (rx1, ry1) = engine.region_bbox(region)
    i0, i1 = max(0, int(np.floor((rx0 - ox) / cell))), min(nx - 1, int(np.ceil((rx1 - ox) / cell)))
    j0, j1 = max(0, int(np.floor((ry0 - oy) / cell))), min(ny - 1, int(np.ceil((ry1 - oy) / cell)))
    if i0 > i1 or j0 > j1:
        return None
    stride = max(1, int(np.ceil(np.sqrt((i1 - i0 + 1) * (j1 - j0 + 1) / MAX_SAMPLES))))
    gx, gy = np.meshgrid(ox + cell * np.arange(i0, i1 + 1, stride), oy + cell * np.arange(j0, j1 + 1, stride))
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    xy = xy[engine.region_contains(region, xy)]
    values = np.asarray(heightfield.map_at(name, xy))
    values = values[np.isfinite(values)]
    if len(values) == 0 or values.max() - values.min() > 1e-6 * max(1.0, float(np.abs(values).max())):
        return None
    return float(values[0])


def value_text(value):
    return f"{value:.3g}"


def one_value_causes(heightfield, region, color_json, categories, terrain_obj):
    """{category: why}: for each of ``categories`` that a paste of the color (JSON) in ``region`` left empty, the
    scene map that explains it, if one does: it holds one value all over the region, and the example held none of
    the category where the map had that value while it showed the value elsewhere (so the color paints none there)."""
    color = json.loads(color_json)["color"]
    causes = {}
    values = {}
    for interaction in color.get("maps", ()):
        category, name = interaction["category"], interaction["map"]
        if category not in categories or category in causes or not is_scene_map(name):
            continue
        if name not in values:
            values[name] = one_value(heightfield, name, region)
        value = values[name]
        if value is None:
            continue
        hist, shown = interaction["hist"], interaction.get("region_hist") or {}
        count = len(hist["values"])
        if count == 0 or not hist["bin_width"] > 0.0:
            continue
        k = int(np.clip(np.floor((value - hist["start"]) / hist["bin_width"]), 0, count - 1))
        seen = not shown.get("values") or shown["values"][k] > 0.0
        if hist["values"][k] == 0.0 and seen:
            causes[category] = (f"the map '{name}' is {value_text(value)} everywhere in the region "
                                f"({source_text(name, terrain_obj)}), and the example had no {category} where it "
                                f"is {value_text(value)}")
    return causes


def constant_in(heightfield, names, region, terrain_obj):
    """Lines saying which of the scene maps ``names`` hold one value all over ``region``: nothing is learned from
    them there."""
    lines = []
    for name in names:
        if is_scene_map(name):
            value = one_value(heightfield, name, region)
            if value is not None:
                lines.append(f"the map '{name}' is {value_text(value)} everywhere in the example's region "
                             f"({source_text(name, terrain_obj)})")
    return lines
