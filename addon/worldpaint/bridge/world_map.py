"""A world painted in Blender: its map of colors on the terrain, its village sites, and the files the world command
line (``python -m worldpaint_engine.world``) fills it from.

The map is a color attribute of the terrain painted with one swatch per palette color (swatch k paints the palette's
color k); the swatches are a Blender palette ("WorldPaint World Map") the vertex paint tools show, so an artist
paints the map with the usual brushes and may change a swatch's color. Each vertex takes the color of the swatch
nearest its own; the labels reach the terrain's grid as one indicator per color, interpolated in the triangles, the
largest one naming the cell's color, so a boundary follows the painted one to within a cell. A village site is an
empty whose ``worldpaint_site`` names its village type, buildings and seed.
"""

import colorsys
import json
import os

import bpy
import numpy as np

from . import WorldPaintError, engine, files, geometry, terrain

SWATCH_PALETTE = "WorldPaint World Map"
SITES_COLLECTION = "WP Village Sites"  # under the WorldPaint collection


def swatch(index):
    """A color (sRGB) for the palette's color ``index``, far from those of the colors before it."""
    hue = (0.33 + index * 0.618034) % 1.0
    return colorsys.hsv_to_rgb(hue, 0.65, 0.85 if index % 2 else 0.65)


def active_index(settings):
    """The palette's active color, within the palette (which has a color)."""
    return min(max(settings.active_color_index, 0), len(settings.palette) - 1)


def swatch_palette(settings):
    """The Blender palette of the map's swatches, one per palette color in order: made or brought to the palette's
    length (a swatch an artist changed keeps its color)."""
    palette = bpy.data.palettes.get(SWATCH_PALETTE) or bpy.data.palettes.new(SWATCH_PALETTE)
    while len(palette.colors) > len(settings.palette):
        palette.colors.remove(palette.colors[-1])
    while len(palette.colors) < len(settings.palette):
        palette.colors.new().color = swatch(len(palette.colors))
    return palette


def swatch_colors(settings):
    """sRGB (K, 3) of the swatches, one per palette color."""
    palette = bpy.data.palettes.get(SWATCH_PALETTE)
    have = [] if palette is None else [tuple(c.color) for c in palette.colors]
    return np.array([have[k] if k < len(have) else swatch(k) for k in range(len(settings.palette))], dtype=np.float64)


def ensure_map(terrain_obj, settings, name):
    """The terrain's map attribute, made when missing (on the vertices, every one painted with the active color's
    swatch) and made the active color attribute; returns it."""
    mesh = terrain_obj.data
    attribute = mesh.color_attributes.get(name)
    if attribute is None:
        attribute = mesh.color_attributes.new(name, 'BYTE_COLOR', 'POINT')
        rgba = np.tile([*swatch_colors(settings)[active_index(settings)], 1.0], len(attribute.data)).astype(np.float32)
        attribute.data.foreach_set("color_srgb", rgba)
    mesh.color_attributes.active_color = attribute
    return attribute


def paint_vertices(terrain_obj, settings, labels):
    """Paints each vertex of the terrain's map with the swatch of its palette color in ``labels`` (int (N,), -1:
    left as it is), its face corners too when the map is on them."""
    attribute = ensure_map(terrain_obj, settings, settings.world.map_attribute)
    mesh = terrain_obj.data
    if attribute.domain == 'CORNER':
        corners = np.empty(len(mesh.loops), dtype=np.int64)
        mesh.loops.foreach_get("vertex_index", corners)
        labels = labels[corners]
    rgba = np.empty(len(attribute.data) * 4, dtype=np.float32)
    attribute.data.foreach_get("color_srgb", rgba)
    rgba = rgba.reshape(-1, 4)
    painted = labels >= 0
    rgba[painted, :3] = swatch_colors(settings)[labels[painted]]
    attribute.data.foreach_set("color_srgb", rgba.ravel())
    mesh.update()


def paint_inside(terrain_obj, settings, shapes, index):
    """Paints the map's vertices inside any of the regions ``shapes`` with the swatch of the palette's color
    ``index``, as a brush would; returns how many vertices were painted."""
    xy = geometry.vertices_world(terrain_obj)[:, :2]
    inside = np.zeros(len(xy), dtype=bool)
    for shape in shapes:
        inside |= engine.region_contains(shape, xy)
    paint_vertices(terrain_obj, settings, np.where(inside, index, -1))
    return int(inside.sum())


def paint_from_image(terrain_obj, settings, image):
    """Paints the map from ``image`` laid over the terrain's extent in XY (its bottom row along the terrain's south
    edge): each vertex takes the palette color whose swatch is nearest the image's pixel under it. Returns the
    vertices painted with each color."""
    width, height = image.size
    if width == 0 or height == 0 or image.channels < 3:
        raise WorldPaintError(f"The image '{image.name}' has no color pixels (is its file missing?)")
    pixels = np.empty(width * height * image.channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(height, width, image.channels)[:, :, :3].astype(np.float64)
    if image.is_float:  # a byte image's pixels are its file's values, a float image's are linear
        pixels = linear_to_srgb(pixels)
    xy = geometry.vertices_world(terrain_obj)[:, :2]
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    span = np.maximum(hi - lo, 1e-9)
    column = np.minimum(((xy[:, 0] - lo[0]) / span[0] * width).astype(np.int64), width - 1)
    row = np.minimum(((xy[:, 1] - lo[1]) / span[1] * height).astype(np.int64), height - 1)
    labels = nearest_swatch(pixels[row, column], swatch_colors(settings))
    paint_vertices(terrain_obj, settings, labels)
    return np.bincount(labels, minlength=len(settings.palette))


def linear_to_srgb(c):
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(np.clip(c, 0.0, None), 1.0 / 2.4) - 0.055)


def vertex_colors(mesh, name):
    """sRGB (N, 3) of the map attribute ``name`` at each vertex of ``mesh`` (a corner or face attribute averaged at
    its vertices); None when the mesh has no such color attribute."""
    attribute = mesh.color_attributes.get(name)
    if attribute is None:
        return None
    rgba = np.empty(len(attribute.data) * 4, dtype=np.float32)
    attribute.data.foreach_get("color_srgb", rgba)
    rgb = rgba.reshape(-1, 4)[:, :3].astype(np.float64)
    if attribute.domain == 'POINT':
        return rgb
    index = np.empty(len(mesh.loops), dtype=np.int64)  # color attributes are on the points or the face corners
    mesh.loops.foreach_get("vertex_index", index)
    counts = np.maximum(np.bincount(index, minlength=len(mesh.vertices)), 1)
    return np.column_stack([np.bincount(index, weights=rgb[:, c], minlength=len(mesh.vertices)) / counts
                            for c in range(3)])


def nearest_swatch(rgb, swatches):
    """Index of the swatch nearest each color of ``rgb`` (N, 3) (of two as near, the first), a swatch at a time: a
    terrain of millions of vertices is not compared with every swatch at once."""
    best = np.full(len(rgb), np.inf)
    label = np.zeros(len(rgb), dtype=np.int64)
    for k, swatch in enumerate(swatches):
        d = ((rgb - swatch) ** 2).sum(axis=1)
        closer = d < best
        best[closer], label[closer] = d[closer], k
    return label


def label_grid(depsgraph, terrain_obj, settings, vertices, triangles, ground):
    """The map painted on the terrain as the engine's grid: (labels uint32 (ny, nx) rows along +Y, each a palette
    index, the grid's corner, cell, the labels used) with the cells of ``ground``, the engine's terrain of the mesh's
    world ``vertices`` and ``triangles``; None when the terrain has no map attribute."""
    evaluated = terrain_obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        rgb = vertex_colors(mesh, settings.world.map_attribute)
    finally:
        evaluated.to_mesh_clear()
    if rgb is None:
        return None
    if len(rgb) != len(vertices):
        raise WorldPaintError(f"The map '{settings.world.map_attribute}' of the terrain '{terrain_obj.name}' does not "
                              "follow its modifiers' vertices: apply them, or paint the map after them")
    labels = nearest_swatch(rgb, swatch_colors(settings))
    used = np.unique(labels)
    grid = ground.grid()
    nx, ny, cell = grid["nx"], grid["ny"], grid["cell"]
    ox, oy = grid["origin"]
    xs, ys = np.meshgrid(ox + np.arange(nx) * cell, oy + np.arange(ny) * cell)
    centres = np.column_stack([xs.ravel(), ys.ravel()])
    if len(used) == 1:
        cells = np.full(nx * ny, used[0])
    else:
        shares = np.empty((len(used), nx * ny))
        for k, label in enumerate(used):
            painted = ground.with_vertex_map("label", vertices, triangles, (labels == label).astype(np.float64))
            shares[k] = np.nan_to_num(painted.map_at("label", centres), nan=-1.0)
        cells = used[np.argmax(shares, axis=0)]
    origin = (ox - 0.5 * cell, oy - 0.5 * cell)  # each sample the centre of its cell
    return cells.reshape(ny, nx).astype(np.uint32), origin, cell, [int(k) for k in used]


def village_sites(scene):
    """The scene's village sites (empties marked as sites), by name."""
    return sorted((obj for obj in scene.objects if obj.worldpaint_site.is_site), key=lambda o: o.name)


def write_ascii_labels(path, labels, origin, cell):
    """An ESRI ASCII grid of labels (rows from the north), placed by its corner."""
    ny, nx = labels.shape
    with open(path, "w", encoding="ascii") as f:
        f.write(f"ncols {nx}\nnrows {ny}\nxllcorner {origin[0]!r}\nyllcorner {origin[1]!r}\ncellsize {cell!r}\n")
        np.savetxt(f, labels[::-1], fmt="%d")


def write_inputs(context, folder):
    """Writes what the world command line fills the scene's world from into ``folder``; returns its arguments (the
    palette, the terrain, the map and its legend or the active color, the sites) and {site's place in the list:
    its empty's name}."""
    scene = context.scene
    settings = scene.worldpaint
    terrain_obj = terrain.terrain_object(context)
    if not len(settings.palette):
        raise WorldPaintError("The palette has no colors: learn or add a color to fill the world with")
    colors = [engine.color_renamed(entry.json, entry.name) for entry in settings.palette]
    with open(os.path.join(folder, "palette.json"), "w", encoding="utf-8") as f:
        f.write(engine.palette_to_json(colors))
    depsgraph = context.evaluated_depsgraph_get()
    vertices, triangles = terrain.mesh_arrays(terrain_obj, depsgraph)
    if len(triangles) == 0:
        raise WorldPaintError(f"The terrain '{terrain_obj.name}' has no faces")
    ground = engine.terrain(vertices, triangles)
    grid = ground.grid()
    np.save(os.path.join(folder, "terrain.npy"), np.asarray(grid["heights"], dtype=np.float64))
    args = ["--palette", "palette.json", "--terrain", "terrain.npy", "--cell", repr(grid["cell"]),
            "--origin", repr(grid["origin"][0]), repr(grid["origin"][1])]
    painted = label_grid(depsgraph, terrain_obj, settings, vertices, triangles, ground)
    if painted is None:
        args += ["--color", settings.palette[active_index(settings)].name]
    else:
        labels, origin, cell, used = painted
        write_ascii_labels(os.path.join(folder, "map.asc"), labels, origin, cell)
        with open(os.path.join(folder, "legend.json"), "w", encoding="utf-8") as f:
            json.dump({str(k): settings.palette[k].name for k in used}, f)
        args += ["--map", "map.asc", "--legend", "legend.json"]
        if settings.world.band > 0.0:
            args += ["--band", repr(settings.world.band)]
    sites = village_sites(scene)
    if sites:
        entries = [{"x": obj.matrix_world.translation.x, "y": obj.matrix_world.translation.y,
                    "type": obj.worldpaint_site.village_type, "buildings": obj.worldpaint_site.buildings,
                    "seed": obj.worldpaint_site.seed} for obj in sites]
        with open(os.path.join(folder, "sites.json"), "w", encoding="utf-8") as f:
            json.dump(entries, f)
        args += ["--villages", "sites.json"]
        # as Generate Village: the panel's file, else the one the .blend holds (Learn Village's types), else none
        path = settings.village.encyclopedia_path
        text = settings.village.encyclopedia_text
        if path:
            args += ["--encyclopedia", files.absolute_path(path, "encyclopedia file")]
        elif text is not None:
            with open(os.path.join(folder, "encyclopedia.json"), "w", encoding="utf-8") as f:
                f.write(text.as_string())
            args += ["--encyclopedia", "encyclopedia.json"]
    return args, {k: obj.name for k, obj in enumerate(sites, start=1)}
