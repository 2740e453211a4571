"""Model variety in the scene: a mesh object's model and component labels for the engine, the parts it is
decomposed into (one collection per component, where the user keeps the edited copies), and the generated variants
written back as meshes sharing the original's materials.

Every part keeps, in the point attribute ``wp_vertex``, which vertex of its component each vertex is: Blender keeps
attributes through edit-mode moves, Lattice and Simple Deform, and through deleting faces, which renumbers the
vertices; the engine numbers a variant's vertices as its component's.
"""

import bpy
import numpy as np

from . import WorldPaintError

VERTEX_ATTRIBUTE = "wp_vertex"
PART_TAG = "wp_part"  # on a part's collection: its original piece (the other objects there are its variants)
COMPONENT_TAG = "wp_component"  # on a part's collection: its component's label
FACE_SET_ATTRIBUTE = ".sculpt_face_set"
COMPONENT_ATTRIBUTE = "wp_component"  # the face attribute Mark Component writes


def mesh_model(mesh, with_uvs=True):
    """The engine's model dict of a mesh's data (object-local coordinates)."""
    n, f, loops = len(mesh.vertices), len(mesh.polygons), len(mesh.loops)
    co = np.empty(n * 3, dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    totals = np.empty(f, dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", totals)
    corners = np.empty(loops, dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    materials = np.empty(f, dtype=np.int64)
    mesh.polygons.foreach_get("material_index", materials)
    uvs = None
    if with_uvs and mesh.uv_layers.active is not None:
        uvs = np.empty(loops * 2, dtype=np.float64)
        mesh.uv_layers.active.data.foreach_get("uv", uvs)
        uvs = uvs.reshape(-1, 2)
    return {"vertices": co.reshape(-1, 3), "loop_totals": totals, "corners": corners, "uvs": uvs,
            "materials": materials}


def seam_islands(obj):
    """int64 (F,): the islands of faces that the edges marked as seams cut the mesh into (a cut along a path of
    existing vertices, seed §4.1: no vertex is added)."""
    mesh = obj.data
    seam = np.empty(len(mesh.edges), dtype=bool)
    mesh.edges.foreach_get("use_seam", seam)
    if not seam.any():
        raise WorldPaintError(f"'{obj.name}' has no seams: mark the cuts between its components as seams (Edit Mode)")
    edge = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("edge_index", edge)
    totals = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", totals)
    face = np.repeat(np.arange(len(totals)), totals)
    parent = np.arange(len(totals))

    def root(f):
        while parent[f] != f:
            parent[f] = parent[parent[f]]
            f = parent[f]
        return f

    first = {}
    for e, f in zip(edge.tolist(), face.tolist(), strict=True):
        if seam[e]:
            continue
        other = first.setdefault(e, f)
        parent[root(f)] = root(other)
    roots = np.array([root(f) for f in range(len(totals))])
    return np.unique(roots, return_inverse=True)[1].astype(np.int64)


def mark_selected_faces(mesh):
    """Gives the selected faces of ``mesh`` a new component label in its face attribute ``wp_component`` (made, with
    every face in component 0, when missing); returns (label, faces marked). An error when no face is selected."""
    selected = np.empty(len(mesh.polygons), dtype=bool)
    mesh.polygons.foreach_get("select", selected)
    if not selected.any():
        raise WorldPaintError("Select the faces of the component first (Edit Mode, face select)")
    attr = mesh.attributes.get(COMPONENT_ATTRIBUTE)
    if attr is not None and (attr.domain != 'FACE' or attr.data_type != 'INT'):
        mesh.attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.attributes.new(COMPONENT_ATTRIBUTE, 'INT', 'FACE')
    labels = np.zeros(len(mesh.polygons), dtype=np.int32)
    attr.data.foreach_get("value", labels)
    label = int(labels.max(initial=0)) + 1
    labels[selected] = label
    attr.data.foreach_set("value", labels)
    return label, int(selected.sum())


def face_labels(obj, source, attribute=""):
    """int64 (F,) component labels of a mesh object's faces: its face sets, its material slots, the islands its seams
    cut, or an integer face attribute."""
    mesh = obj.data
    name = {"FACE_SETS": FACE_SET_ATTRIBUTE, "ATTRIBUTE": attribute}.get(source)
    labels = np.empty(len(mesh.polygons), dtype=np.int64)
    if source == 'SEAMS':
        return seam_islands(obj)
    if source == 'MATERIALS':
        mesh.polygons.foreach_get("material_index", labels)
        return labels
    attr = mesh.attributes.get(name) if name else None
    if attr is None or attr.domain != 'FACE' or attr.data_type not in {'INT', 'INT8', 'BOOLEAN'}:
        what = "face sets (Sculpt Mode > Face Sets)" if source == 'FACE_SETS' else f"an integer face attribute '{name}'"
        raise WorldPaintError(f"'{obj.name}' has no {what} to decompose it by")
    values = np.empty(len(mesh.polygons), dtype=np.int64 if attr.data_type != 'BOOLEAN' else bool)
    attr.data.foreach_get("value", values)
    return values.astype(np.int64) - min(0, int(values.min(initial=0)))


def part_mesh(name, part, materials):
    """A mesh of a component's sub-mesh (engine model dict), its vertices numbered in ``wp_vertex``."""
    mesh = bpy.data.meshes.new(name)
    write_model(mesh, part, materials)
    attr = mesh.attributes.new(VERTEX_ATTRIBUTE, 'INT', 'POINT')
    attr.data.foreach_set("value", np.arange(len(mesh.vertices), dtype=np.int32))
    return mesh


def write_model(mesh, model, materials):
    """Fills an empty mesh with an engine model dict (positions, faces, UVs, material indices) and ``materials``.

    Written for a thousand variants in well under a second: positions, corners, material indices and UVs go straight
    into their attributes (one copy each, no per-item conversion), Blender computes the edges, and nothing is
    validated (the engine checked the model: indices in range, no repeated corner).
    """
    vertices = np.asarray(model["vertices"], dtype=np.float32)
    totals = np.asarray(model["loop_totals"], dtype=np.int32)
    corners = np.asarray(model["corners"], dtype=np.int32)
    mesh.vertices.add(len(vertices))
    mesh.loops.add(len(corners))
    mesh.polygons.add(len(totals))
    attributes = mesh.attributes
    attributes["position"].data.foreach_set("vector", vertices.ravel())
    corner_vert = attributes.get(".corner_vert")
    if corner_vert is not None:
        corner_vert.data.foreach_set("value", corners)
    else:
        mesh.loops.foreach_set("vertex_index", corners)
    mesh.polygons.foreach_set("loop_start", np.cumsum(totals, dtype=np.int32) - totals)
    for material in materials:
        mesh.materials.append(material)
    indices = model.get("materials")
    if indices is not None and len(materials) and np.any(indices):
        attributes.new("material_index", 'INT', 'FACE').data.foreach_set("value",
                                                                         np.asarray(indices, dtype=np.int32))
    if model.get("uvs") is not None:
        uvs = attributes.new("UVMap", 'FLOAT2', 'CORNER')
        uvs.data.foreach_set("vector", np.asarray(model["uvs"], dtype=np.float32).ravel())
    mesh.update(calc_edges=True)


def write_variants(collection, name, models, materials):
    """One mesh object per engine model dict in ``collection``, named ``name variant 000`` on; returns them."""
    objects = []
    for k, model in enumerate(models):
        mesh = bpy.data.meshes.new(f"{name} variant {k:03d}")
        write_model(mesh, model, materials)
        objects.append(bpy.data.objects.new(mesh.name, mesh))
        collection.objects.link(objects[-1])
    return objects


def part_path(parts, collection, default):
    """How messages name a part: its collection under the model's parts collection ("Tree Parts/Tree part 2")."""
    name = collection.name if collection is not None else default
    return f"{parts.name}/{name}" if parts is not None else name


def object_mode_change(relative, tolerance=1e-6):
    """What a copy's Object Mode transform (``relative``: its matrix in its piece's frame) does, in words ("turned",
    "moved and scaled"), or "" when it is the piece's own."""
    location, rotation, scale = relative.decompose()
    words = [word for word, changed in (
        ("moved", location.length > tolerance),
        ("turned", rotation.angle > tolerance),
        ("scaled", max(abs(s - 1.0) for s in scale) > tolerance)) if changed]
    return " and ".join(words)


def variant_model(obj, original, where="", matrix=None):
    """The engine model of an edited part (modifiers applied), its vertices renumbered as the component's: vertex
    ``k`` of the component first (its original place, ``original`` model dict, where the edit deleted it), new ones
    after. ``matrix`` (the copy's Object Mode transform in its piece's frame) moves the copy's vertices: the transform
    is read as part of the copy. ``where`` names the part's collection in messages."""
    place = f" in '{where}'" if where else ""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        model = mesh_model(mesh)
        attr = mesh.attributes.get(VERTEX_ATTRIBUTE)
        if attr is None or attr.domain != 'POINT':
            raise WorldPaintError(f"'{obj.name}'{place} is not a copy of a part made by Decompose Model "
                                  f"(it has no '{VERTEX_ATTRIBUTE}' attribute)")
        ids = np.empty(len(mesh.vertices), dtype=np.int64)
        attr.data.foreach_get("value", ids)
    finally:
        evaluated.to_mesh_clear()
    if matrix is not None:
        m = np.array(matrix, dtype=np.float64)
        model["vertices"] = model["vertices"] @ m[:3, :3].T + m[:3, 3]
    bad = np.flatnonzero(~np.isfinite(model["vertices"]).all(axis=1))
    if len(bad):
        moved = " once its Object Mode transform is applied" if matrix is not None else ""
        raise WorldPaintError(f"'{obj.name}'{place} has a vertex that is not a finite number{moved} (vertex "
                              f"{int(bad[0])} at {tuple(float(x) for x in model['vertices'][bad[0]])}): move it "
                              "or delete the copy")
    base = np.asarray(original["vertices"], dtype=np.float64)
    n = len(base)
    if len(ids) and ids.max() >= n:
        raise WorldPaintError(f"'{obj.name}'{place} is not a copy of that part's piece: its vertices are numbered "
                              f"0 to {int(ids.max())} (attribute '{VERTEX_ATTRIBUTE}') where the piece's are 0 to "
                              f"{n - 1}, so it is a copy of another part's piece (put it in that part's collection)")
    known = (ids >= 0) & (ids < n)
    first = np.zeros(len(ids), dtype=bool)
    _, firsts = np.unique(np.where(known, ids, -1 - np.arange(len(ids))), return_index=True)
    first[firsts] = True
    keep = known & first  # a vertex an edit duplicated (extrude) copies its id: the first keeps the place
    index = np.empty(len(ids), dtype=np.int64)
    index[keep] = ids[keep]
    extra = np.nonzero(~keep)[0]
    index[extra] = n + np.arange(len(extra))
    vertices = np.vstack([base, model["vertices"][extra]])
    vertices[ids[keep]] = model["vertices"][keep]
    model["vertices"] = vertices
    model["corners"] = index[model["corners"]]
    return model


def hide_collection(scene, collection):
    """Keeps a collection out of the view layer (prototype collections are instanced, never shown themselves)."""
    layer = scene.view_layers[0].layer_collection
    stack = [layer]
    while stack:
        item = stack.pop()
        if item.collection == collection:
            item.exclude = True
            return
        stack.extend(item.children)
