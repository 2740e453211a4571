"""The demo's look: Cycles on the CPU, a sky with a sun and simple materials made by code (terrain graded by its
slope, bark and leaves, rocks, grass, plaster walls and tiled roofs, roads, water, vines), and the cameras.

Everything here works on Blender 4.5 LTS and 5.x: the sky's model is picked from what the Sky Texture node offers
(5.x renamed Nishita to single and multiple scattering), and a world of a plain gradient stands in where it offers
neither. Colours are linear (what the Principled BSDF's Base Color takes)."""

import math
import re
import time

import bpy
import numpy as np
from mathutils import Vector

# --- render settings ----------------------------------------------------------------------------------------------


def has_openimagedenoise():
    """Whether this Blender's Cycles was built with OpenImageDenoise (the CPU denoiser)."""
    try:
        import _cycles
    except ImportError:
        return False
    return bool(getattr(_cycles, "with_openimagedenoise", False))


def cycles(scene, samples=32):
    """Cycles on the CPU with few samples, denoised by OpenImageDenoise where Blender has it (else twice the samples,
    undenoised), and few bounces: outdoor light needs little more than the first two."""
    scene.render.engine = 'CYCLES'
    settings = scene.cycles
    settings.device = 'CPU'
    denoise = has_openimagedenoise()
    settings.samples = samples if denoise else 2 * samples
    settings.use_adaptive_sampling = True
    settings.adaptive_threshold = 0.05
    settings.use_denoising = denoise
    if denoise:
        settings.denoiser = 'OPENIMAGEDENOISE'
        settings.denoising_input_passes = 'RGB_ALBEDO_NORMAL'
        settings.denoising_prefilter = 'ACCURATE'
        if hasattr(settings, "denoising_use_gpu"):
            settings.denoising_use_gpu = False
    settings.max_bounces = 4
    settings.diffuse_bounces = 2
    settings.glossy_bounces = 2
    settings.transmission_bounces = 2
    settings.transparent_max_bounces = 4
    settings.caustics_reflective = settings.caustics_refractive = False
    settings.sample_clamp_indirect = 5.0  # no fireflies from the sun bouncing off the water
    scene.render.use_persistent_data = True  # one scene, many cameras: its geometry is prepared once
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGB'
    scene.render.image_settings.color_depth = '8'
    scene.render.image_settings.compression = 90
    view = scene.view_settings
    transforms = _enum_items(view, "view_transform")
    view.view_transform = 'AgX' if 'AgX' in transforms else 'Filmic' if 'Filmic' in transforms else view.view_transform
    looks = [look for look in _enum_items(view, "look") if look.endswith("Medium High Contrast")]
    if looks:
        view.look = looks[0]
    view.exposure = 0.0
    return denoise


def _enum_items(owner, prop):
    return [item.identifier for item in owner.bl_rna.properties[prop].enum_items]


# --- sky and sun --------------------------------------------------------------------------------------------------

SUN_ELEVATION = 32.0  # degrees: low enough for long shadows that show the relief, high enough for daylight
SUN_AZIMUTH = 235.0  # degrees clockwise from north (+Y): from the south-west, across most views


def sun_direction(elevation, azimuth):
    """The unit vector from the ground towards the sun."""
    e, a = math.radians(elevation), math.radians(azimuth)
    return Vector((math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)))


def sky(scene, elevation=SUN_ELEVATION, azimuth=SUN_AZIMUTH, strength=0.15):
    """A physical sky (Nishita in 4.x, multiple scattering in 5.x) whose sun stands where the lamp's does, its disc
    left to the lamp; a gradient from a pale horizon to a blue zenith where the node has neither model."""
    world = scene.world or bpy.data.worlds.new("Sky")
    scene.world = world
    if world.node_tree is None:
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputWorld")
    background = nodes.new("ShaderNodeBackground")
    background.inputs["Strength"].default_value = strength
    links.new(background.outputs["Background"], out.inputs["Surface"])
    texture = nodes.new("ShaderNodeTexSky")
    models = _enum_items(texture, "sky_type")
    model = next((m for m in ("MULTIPLE_SCATTERING", "NISHITA") if m in models), None)
    if model is None:
        nodes.remove(texture)
        _gradient_sky(nodes, links, background)
        return world
    texture.sky_type = model
    texture.sun_disc = False
    texture.sun_elevation = math.radians(elevation)
    # the node turns its sun from +Y towards -X as the rotation grows: azimuth is measured the other way
    texture.sun_rotation = math.radians(-azimuth)
    texture.altitude = 300.0
    for name, value in (("air_density", 1.0), ("dust_density", 0.5), ("aerosol_density", 0.5),
                        ("ozone_density", 1.0)):
        if hasattr(texture, name):
            setattr(texture, name, value)
    _below_horizon(nodes, links, texture.outputs["Color"], background)
    return world


def _below_horizon(nodes, links, sky_color, background):
    """Where the view points below the horizon the sky model draws a dark ground: the air's colour (the haze the far
    land fades into) shows there instead, wherever the land ends."""
    coordinates = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coordinates.outputs["Generated"], split.inputs["Vector"])
    below = nodes.new("ShaderNodeMath")
    below.operation = 'LESS_THAN'
    below.inputs[1].default_value = 0.0
    links.new(split.outputs["Z"], below.inputs[0])
    mix = nodes.new("ShaderNodeMix")
    mix.data_type = 'RGBA'
    links.new(below.outputs["Value"], mix.inputs["Factor"])
    links.new(sky_color, mix.inputs["A"])
    mix.inputs["B"].default_value = (*(c * HAZE_STRENGTH / background.inputs["Strength"].default_value
                                       for c in HAZE), 1.0)
    links.new(mix.outputs["Result"], background.inputs["Color"])


def _gradient_sky(nodes, links, background):
    coordinates = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position = 0.0
    ramp.color_ramp.elements[0].color = (0.55, 0.65, 0.80, 1.0)
    ramp.color_ramp.elements[1].position = 0.6
    ramp.color_ramp.elements[1].color = (0.12, 0.25, 0.60, 1.0)
    links.new(coordinates.outputs["Generated"], split.inputs["Vector"])
    links.new(split.outputs["Z"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = 1.0


def sun(scene, elevation=SUN_ELEVATION, azimuth=SUN_AZIMUTH, strength=4.0, angle=2.0):
    """A sun lamp shining from ``elevation`` and ``azimuth`` (degrees), its ``angle`` (degrees) softening the
    shadows' edges."""
    light = bpy.data.lights.get("Sun") or bpy.data.lights.new("Sun", 'SUN')
    light.energy = strength
    light.angle = math.radians(angle)
    light.color = (1.0, 0.96, 0.9)
    obj = bpy.data.objects.get("Sun") or bpy.data.objects.new("Sun", light)
    if obj.name not in scene.collection.objects:
        scene.collection.objects.link(obj)
    obj.rotation_euler = (-sun_direction(elevation, azimuth)).to_track_quat('-Z', 'Y').to_euler()
    return obj


# --- materials ----------------------------------------------------------------------------------------------------


HAZE = (0.40, 0.50, 0.68)  # the horizon's colour under the sky below
HAZE_STRENGTH = 0.6
HAZE_DISTANCE = 3000.0  # metres over which 63 % of a surface's light gives way to the air's


class Shader:
    """A material's node tree rebuilt from nothing: a Principled BSDF into the output, and helpers to feed it."""

    def __init__(self, material):
        if material.node_tree is None:  # 4.5: a new material has no node tree until it uses nodes
            material.use_nodes = True
        self.tree = material.node_tree
        self.tree.nodes.clear()
        self.bsdf = self.node("ShaderNodeBsdfPrincipled")
        self.out = self.node("ShaderNodeOutputMaterial")
        self.link(self.haze(self.bsdf.outputs["BSDF"]), self.out.inputs["Surface"])

    def haze(self, shader):
        """Aerial perspective at the cost of a mix: seen from the camera, a surface fades into the horizon's colour
        with its distance (``1 - exp(-d / HAZE_DISTANCE)``), as the far hills do in the air, without the price of a
        volume."""
        distance = self.node("ShaderNodeCameraData").outputs["View Distance"]
        fade = self.math('SUBTRACT', 1.0, self.math('EXPONENT', self.math('MULTIPLY', distance,
                                                                          -1.0 / HAZE_DISTANCE), 0.0))
        camera_ray = self.node("ShaderNodeLightPath").outputs["Is Camera Ray"]
        air = self.node("ShaderNodeEmission")
        air.inputs["Color"].default_value = (*HAZE, 1.0)
        air.inputs["Strength"].default_value = HAZE_STRENGTH
        mix = self.node("ShaderNodeMixShader")
        self.link(self.math('MULTIPLY', fade, camera_ray), mix.inputs["Fac"])
        self.link(shader, mix.inputs[1])
        self.link(air.outputs["Emission"], mix.inputs[2])
        return mix.outputs["Shader"]

    def node(self, kind, **settings):
        node = self.tree.nodes.new(kind)
        for key, value in settings.items():
            setattr(node, key, value)
        return node

    def link(self, output, socket):
        self.tree.links.new(output, socket)

    def ramp(self, fac, stops, interpolation='LINEAR'):
        """A Color Ramp of ``stops`` ((position, rgb), ...) driven by ``fac``; returns its colour output."""
        node = self.node("ShaderNodeValToRGB")
        elements = node.color_ramp.elements
        node.color_ramp.interpolation = interpolation
        for _ in range(len(stops) - len(elements)):
            elements.new(0.5)
        for element, (position, rgb) in zip(elements, stops, strict=True):
            element.position = position
            element.color = (*rgb, 1.0)
        self.link(fac, node.inputs["Fac"])
        return node.outputs["Color"]

    def noise(self, scale, detail=3.0, vector=None):
        """Noise (0-1, around 0.5) of features ``1 / scale`` long, in object space unless ``vector`` is given."""
        node = self.node("ShaderNodeTexNoise")
        node.inputs["Scale"].default_value = scale
        node.inputs["Detail"].default_value = detail
        if vector is not None:
            self.link(vector, node.inputs["Vector"])
        return node.outputs["Fac"]

    def math(self, operation, a, b):
        node = self.node("ShaderNodeMath", operation=operation)
        for socket, value in zip(node.inputs, (a, b), strict=False):
            if isinstance(value, float | int):
                socket.default_value = value
            else:
                self.link(value, socket)
        return node.outputs["Value"]

    def random(self):
        """A number in [0, 1) per object and per instance: no two trees quite the same green."""
        return self.node("ShaderNodeObjectInfo").outputs["Random"]

    def bump(self, height, strength):
        node = self.node("ShaderNodeBump")
        node.inputs["Strength"].default_value = strength
        self.link(height, node.inputs["Height"])
        self.link(node.outputs["Normal"], self.bsdf.inputs["Normal"])

    def surface(self, color, roughness=0.8):
        """Sets the Base Color (an rgb or a colour output) and the Roughness."""
        if isinstance(color, tuple):
            self.bsdf.inputs["Base Color"].default_value = (*color, 1.0)
        else:
            self.link(color, self.bsdf.inputs["Base Color"])
        self.bsdf.inputs["Roughness"].default_value = roughness


def terrain(material):
    """Grass on gentle slopes, rock on steep ones (the geometry's normal through a ramp, its edge broken by noise),
    the grass patchy between a lush and a dry green over tens of metres."""
    s = Shader(material)
    geometry = s.node("ShaderNodeNewGeometry")
    position = geometry.outputs["Position"]
    up = s.node("ShaderNodeSeparateXYZ")
    s.link(geometry.outputs["Normal"], up.inputs["Vector"])
    broken = s.math('ADD', up.outputs["Z"], s.math('MULTIPLY', s.noise(0.08, 2.0, position), 0.12))
    grass = s.ramp(s.noise(0.012, 2.0, position), ((0.35, (0.045, 0.10, 0.018)), (0.65, (0.13, 0.15, 0.04))))
    mix = s.node("ShaderNodeMix", data_type='RGBA')
    s.link(s.ramp(broken, ((0.74, (0.0, 0.0, 0.0)), (0.78, (1.0, 1.0, 1.0)))), mix.inputs["Factor"])
    s.link(s.ramp(s.noise(0.15, 2.0, position), ((0.3, (0.09, 0.085, 0.075)), (0.7, (0.17, 0.15, 0.12)))),
           mix.inputs["A"])
    s.link(grass, mix.inputs["B"])
    s.surface(mix.outputs["Result"], 0.95)


def far_land(material):
    """The land around the scene seen from afar: fields and woods in patches a few hundred metres across, rock where
    the mountains are steep."""
    s = Shader(material)
    geometry = s.node("ShaderNodeNewGeometry")
    position = geometry.outputs["Position"]
    up = s.node("ShaderNodeSeparateXYZ")
    s.link(geometry.outputs["Normal"], up.inputs["Vector"])
    land = s.ramp(s.noise(0.004, 3.0, position), ((0.5, (0.015, 0.035, 0.01)), (0.54, (0.08, 0.12, 0.03)),
                                                  (0.7, (0.15, 0.16, 0.05))))
    mix = s.node("ShaderNodeMix", data_type='RGBA')
    s.link(s.ramp(up.outputs["Z"], ((0.7, (0.0, 0.0, 0.0)), (0.8, (1.0, 1.0, 1.0)))), mix.inputs["Factor"])
    mix.inputs["A"].default_value = (0.14, 0.13, 0.12, 1.0)
    s.link(land, mix.inputs["B"])
    s.surface(mix.outputs["Result"], 0.95)


def leaves(material, rgb=(0.030, 0.085, 0.018), spread=0.6):
    """Foliage whose green changes a little from one tree to the next."""
    s = Shader(material)
    dark = tuple(c * (1.0 - 0.5 * spread) for c in rgb)
    light = tuple(c * (1.0 + spread) for c in rgb)
    s.surface(s.ramp(s.random(), ((0.0, dark), (1.0, light))), 0.7)


def plain(material, rgb, roughness=0.8, grain=0.0, grain_scale=2.0):
    """One colour, optionally grained by noise (``grain``: how much darker the darkest grain is)."""
    s = Shader(material)
    if grain:
        dark = tuple(c * (1.0 - grain) for c in rgb)
        s.surface(s.ramp(s.noise(grain_scale, 2.0), ((0.3, dark), (0.7, rgb))), roughness)
    else:
        s.surface(rgb, roughness)


def block_house(material, wall=(0.55, 0.47, 0.36), roof=(0.30, 0.07, 0.035)):
    """A box house in one material: its top faces a tiled roof, its sides plaster walls."""
    s = Shader(material)
    up = s.node("ShaderNodeSeparateXYZ")
    s.link(s.node("ShaderNodeNewGeometry").outputs["Normal"], up.inputs["Vector"])
    s.surface(s.ramp(up.outputs["Z"], ((0.5, wall), (0.51, roof))), 0.8)


def water(material):
    """Dark clear water reflecting the sky, foam where the mesh's ``foam`` says, glossier where it is slow."""
    s = Shader(material)
    foam = s.node("ShaderNodeAttribute", attribute_name="foam").outputs["Fac"]
    s.surface(s.ramp(foam, ((0.4, (0.012, 0.045, 0.05)), (1.0, (0.7, 0.75, 0.78)))), 0.05)
    speed = s.node("ShaderNodeAttribute", attribute_name="speed").outputs["Fac"]
    rough = s.node("ShaderNodeMapRange")
    rough.inputs["From Max"].default_value = 10.0
    rough.inputs["To Min"].default_value = 0.03
    rough.inputs["To Max"].default_value = 0.3
    s.link(speed, rough.inputs["Value"])
    s.link(rough.outputs["Result"], s.bsdf.inputs["Roughness"])


BARK = (0.075, 0.045, 0.025)
LEAVES = (0.030, 0.085, 0.018)
ROCK = (0.20, 0.19, 0.17)
LOOKS = {  # material name (without Blender's .001 suffixes) -> how it is shaded
    "Terrain": terrain,
    "Far land": far_land,
    "Tree": leaves,
    "Leaves": leaves,
    "Bark": lambda m: plain(m, BARK, 0.9, 0.4, 8.0),
    "Birch bark": lambda m: plain(m, (0.55, 0.53, 0.48), 0.7, 0.5, 6.0),
    "Birch leaves": lambda m: leaves(m, (0.07, 0.16, 0.03), 0.5),
    "Grass": lambda m: leaves(m, (0.07, 0.16, 0.02), 0.5),
    "Vine": lambda m: leaves(m, (0.06, 0.14, 0.02), 0.4),
    "Rock": lambda m: plain(m, ROCK, 0.85, 0.35, 1.5),
    "WorldPaint Rock": lambda m: plain(m, ROCK, 0.85, 0.35, 1.5),
    "Road": lambda m: plain(m, (0.22, 0.17, 0.12), 0.95, 0.3, 0.5),
    "House": block_house,
    "Wall": lambda m: plain(m, (0.60, 0.52, 0.40), 0.85, 0.15, 1.0),
    "Roof": lambda m: plain(m, (0.32, 0.075, 0.035), 0.7, 0.2, 3.0),
    "WP Wall": lambda m: plain(m, (0.60, 0.55, 0.46), 0.85, 0.15, 1.0),  # the imported places' buildings
    "WP Roof": lambda m: plain(m, (0.30, 0.08, 0.04), 0.7, 0.2, 3.0),
    "Door": lambda m: plain(m, (0.10, 0.05, 0.02), 0.6),
    "Window": lambda m: plain(m, (0.01, 0.015, 0.02), 0.1),
    "Foundation": lambda m: plain(m, (0.22, 0.21, 0.19), 0.9, 0.3, 2.0),
    "WorldPaint Water": water,
}


def dress_materials():
    """Gives every material the demo makes its look from ``LOOKS``; returns the names of those left as they were."""
    untouched = []
    for material in bpy.data.materials:
        look = LOOKS.get(re.sub(r"\.\d{3}$", "", material.name))
        if look is None:
            untouched.append(material.name)
        else:
            look(material)
    return untouched


def bark_and_leaves(tree, crown_part=2):
    """Two material slots on a tree whose integer face attribute ``part`` labels its parts: bark on the trunk, leaves
    on the crown (part ``crown_part``). Its variants keep them."""
    mesh = tree.data
    old = list(mesh.materials)
    parts = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.attributes["part"].data.foreach_get("value", parts)
    mesh.materials.clear()
    mesh.materials.append(bpy.data.materials.get("Bark") or bpy.data.materials.new("Bark"))
    mesh.materials.append(bpy.data.materials.get("Leaves") or bpy.data.materials.new("Leaves"))
    mesh.polygons.foreach_set("material_index", (parts == crown_part).astype(np.int32))
    mesh.update()
    for material in old:
        if material is not None and material.users == 0:
            bpy.data.materials.remove(material)


def smooth(obj):
    """Smooth shading on a mesh (a terrain's facets would show in the light)."""
    obj.data.polygons.foreach_set("use_smooth", np.ones(len(obj.data.polygons), dtype=bool))
    obj.data.update()


# --- land to the horizon -----------------------------------------------------------------------------------------

def backdrop(name, origin, cell, heights, rings=(0, 2, 6, 14, 30, 60, 120, 250, 500, 900, 1500, 2500),
             relief=1.0):
    """Land around a grid terrain out to the horizon, so that no picture shows where the terrain ends: rings of
    vertices going out from its edge (fanned at the corners), at the edge's own height there, settling into rolling
    fields a few hundred metres out and rising to a range of mountains from 3 km away (``relief`` scales both; 0: a
    plain)."""
    heights = np.asarray(heights, dtype=np.float64)
    ny, nx = heights.shape
    x0, y0 = origin
    x1, y1 = x0 + cell * (nx - 1), y0 + cell * (ny - 1)
    # the edge counter-clockwise from the south-west corner: its points, heights and outward directions
    south = [(x0 + cell * i, y0, heights[0, i], 0.0, -1.0) for i in range(nx - 1)]
    east = [(x1, y0 + cell * j, heights[j, -1], 1.0, 0.0) for j in range(ny - 1)]
    north = [(x1 - cell * i, y1, heights[-1, -1 - i], 0.0, 1.0) for i in range(nx - 1)]
    west = [(x0, y1 - cell * j, heights[-1 - j, 0], -1.0, 0.0) for j in range(ny - 1)]
    edge = []
    for side in (south, east, north, west):
        x, y, z, dx, dy = side[0]
        outward = math.atan2(dy, dx)  # a quarter turn on from the previous side's: fanned at the corner
        edge += [(x, y, z, math.cos(a), math.sin(a)) for a in np.linspace(outward - math.pi / 2, outward, 9)]
        edge += side[1:]
    edge = np.array(edge)
    radii = np.concatenate([rings, np.arange(4000.0, 32001.0, 1000.0)])
    px = edge[:, 0, None] + radii[None, :] * edge[:, 3, None]
    py = edge[:, 1, None] + radii[None, :] * edge[:, 4, None]
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    far = np.hypot(px - centre[0], py - centre[1])
    bearing = np.arctan2(py - centre[1], px - centre[0])
    fields = 30.0 * np.sin(px / 310.0) * np.cos(py / 270.0) + 12.0 * np.sin((px + py) / 170.0)
    ridge = 0.65 + 0.18 * np.sin(3.0 * bearing + 1.0) + 0.1 * np.sin(7.0 * bearing) + 0.08 * np.sin(17.0 * bearing)
    mountains = 1200.0 * ridge * np.clip((far - 3000.0) / 6000.0, 0.0, 1.0) ** 1.5
    near = np.exp(-radii / 250.0)[None, :]
    z = edge[:, 2, None] * near + relief * (fields + mountains) * (1.0 - near)
    co = np.column_stack([px.ravel(), py.ravel(), z.ravel()])
    n, m = px.shape
    k, j = np.meshgrid(np.arange(n), np.arange(m - 1), indexing='ij')
    v0 = (k * m + j).ravel()
    v1 = (((k + 1) % n) * m + j).ravel()
    quads = np.column_stack([v0, v0 + 1, v1 + 1, v1])
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(co.tolist(), [], quads.tolist())
    mesh.materials.append(bpy.data.materials.get("Far land") or bpy.data.materials.new("Far land"))
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    smooth(obj)
    return obj


# --- cameras and pictures -----------------------------------------------------------------------------------------


def camera(name, location, target, lens=35.0, scene=None):
    """A perspective camera at ``location`` looking at ``target``, made once per name."""
    scene = scene or bpy.context.scene
    obj = bpy.data.objects.get(name)
    if obj is None:
        obj = bpy.data.objects.new(name, bpy.data.cameras.new(name))
        scene.collection.objects.link(obj)
    obj.data.lens = lens
    obj.data.clip_start = 0.5
    obj.data.clip_end = 5000.0
    obj.location = location
    obj.rotation_euler = (Vector(target) - Vector(location)).to_track_quat('-Z', 'Y').to_euler()
    return obj


def strokes_in_view(cam, strokes, scene, width=0.003, rgb=(1.0, 0.45, 0.05)):
    """Strokes drawn over a camera's picture (points in its frame, 0-1) as glowing lines just in front of its lens,
    ``width`` of the picture's width wide: what the artist sketched, seen in the render."""
    frame = cam.data.view_frame(scene=scene)
    xs, ys, depth = [v.x for v in frame], [v.y for v in frame], -frame[0].z
    scale = 2.0 * cam.data.clip_start / depth  # the lines lie twice the clip distance in front of the lens
    material = bpy.data.materials.get("Stroke") or bpy.data.materials.new("Stroke")
    s = Shader(material)
    glow = s.node("ShaderNodeEmission")
    glow.inputs["Color"].default_value = (*rgb, 1.0)
    glow.inputs["Strength"].default_value = 3.0
    s.link(glow.outputs["Emission"], s.out.inputs["Surface"])
    curve = bpy.data.curves.new("Strokes", 'CURVE')
    curve.dimensions = '3D'
    curve.bevel_depth = 0.5 * width * (max(xs) - min(xs)) * scale
    curve.materials.append(material)
    for stroke in strokes:
        spline = curve.splines.new('POLY')
        spline.points.add(len(stroke) - 1)
        for point, (x, y) in zip(spline.points, stroke, strict=True):
            local = Vector((min(xs) + x * (max(xs) - min(xs)), min(ys) + y * (max(ys) - min(ys)), -depth)) * scale
            point.co = (*local, 1.0)
    obj = bpy.data.objects.new("Strokes", curve)
    obj.parent = cam
    obj.visible_shadow = False
    scene.collection.objects.link(obj)
    return obj


def render(scene, cam, path, resolution=(1280, 720)):
    """Renders the scene through ``cam`` to the PNG ``path``; returns the seconds it took."""
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.render.filepath = str(path)
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True, scene=scene.name)
    return time.perf_counter() - start
