"""Texture variety in the scene (Maréchal et al. §5): a model's base texture and its texture edits as arrays for the
engine, the texture component atlases it returns written as images, and the materials that show them.

Images cross as uint8 (H, W, 4) RGBA, rows from the bottom as ``Image.pixels`` holds them (8 bits a channel: a float
texture is rounded). The edits and atlases that worldpaint makes are packed into the .blend, so they travel with it;
an edit painted after it was made is packed again when the file is saved. A face shows an atlas through
a copy of its material whose image textures of the base texture show the atlas instead; the texture coordinates are
never touched.
"""

import bpy
import numpy as np

from . import WorldPaintError

ATLAS_TAG = "wp_atlas"  # on an atlas material: the atlas image it shows
FACE_ATTRIBUTE = "wp_face"  # on a generated variant: the original face each face copies (-1: added by an edit)


def image_textures(material):
    """The Image Texture nodes of a material's node tree."""
    if material is None or material.node_tree is None:
        return []
    return [node for node in material.node_tree.nodes if node.type == 'TEX_IMAGE']


def object_materials(obj):
    """The materials of a mesh object's slots, as the generated variants get them."""
    return [slot.material for slot in obj.material_slots if slot.material is not None]


def base_image(obj):
    """The texture an object's edits are painted over: its setting, else the first image texture of its materials."""
    chosen = obj.worldpaint_variety.base_image
    if chosen is not None:
        return chosen
    for material in object_materials(obj):
        for node in image_textures(material):
            if node.image is not None:
                return node.image
    raise WorldPaintError(f"'{obj.name}' has no base texture: give one of its materials an Image Texture, or set "
                          "Base Texture in the Model Variety panel")


def image_rgba(image):
    """uint8 (H, W, 4): an image's pixels as the engine reads them."""
    width, height = image.size
    if width == 0 or height == 0:
        raise WorldPaintError(f"Image '{image.name}' has no pixels (is its file missing?)")
    channels = image.channels
    pixels = np.empty(width * height * channels, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(height, width, channels)
    rgba = np.ones((height, width, 4), dtype=np.float32)
    rgba[:, :, :min(channels, 4)] = pixels[:, :, :4]
    if channels < 3:
        rgba[:, :, 1:3] = pixels[:, :, :1]
    return np.rint(np.clip(rgba, 0.0, 1.0) * 255.0).astype(np.uint8)


def new_image(name, rgba, like):
    """A new image of uint8 (H, W, 4) pixels in the colour space of ``like``, packed into the .blend."""
    height, width = rgba.shape[:2]
    image = bpy.data.images.new(name, width, height, alpha=True)
    image.colorspace_settings.name = like.colorspace_settings.name
    image.pixels.foreach_set((rgba.astype(np.float32) / 255.0).ravel())
    image.pack()
    return image


def edit_copy(base, name):
    """A new texture edit: a packed copy of the base texture's pixels (never of its file, which painting and saving
    the copy would overwrite)."""
    return new_image(name, image_rgba(base), base)


def texture_inputs(obj, model):
    """The base texture and the edits of a decomposed object, checked, as (base image, base pixels, [edit images],
    [edit pixels]); ``model`` is its engine model dict (the edits are painted through its UVs)."""
    settings = obj.worldpaint_variety
    if model.get("uvs") is None:
        raise WorldPaintError(f"'{obj.name}' has no UV map: unwrap it (UV > Unwrap) before painting texture edits")
    base = base_image(obj)
    if not any(node.image == base for m in object_materials(obj) for node in image_textures(m)):
        raise WorldPaintError(f"No material of '{obj.name}' shows the base texture '{base.name}' in an Image Texture")
    base_pixels = image_rgba(base)
    images, pixels = [], []
    for k, item in enumerate(settings.texture_edits):
        image = item.image
        if image is None:
            raise WorldPaintError(f"Texture edit {k + 1} of '{obj.name}' has no image")
        if image == base:
            raise WorldPaintError(f"Texture edit '{image.name}' is the base texture itself: paint on a copy "
                                  "(New Texture Edit)")
        if tuple(image.size) != tuple(base.size):
            raise WorldPaintError(f"Texture edit '{image.name}' is {image.size[0]}×{image.size[1]} pixels but the "
                                  f"base texture '{base.name}' is {base.size[0]}×{base.size[1]}: paint on a copy "
                                  "of the base texture (New Texture Edit)")
        images.append(image)
        pixels.append(image_rgba(image))
    return base, base_pixels, images, pixels


def keep_painting():
    """Packs again the packed texture edits painted since they were packed, so the .blend keeps what was painted
    (called as the file is saved: packing in an operator would make its undo reload the unpainted image)."""
    images = {item.image.name: item.image for obj in bpy.data.objects
              for item in obj.worldpaint_variety.texture_edits if item.image is not None}
    for image in images.values():
        if image.packed_file is not None and image.is_dirty:
            image.pack()


def atlas_materials(materials, base, atlases):
    """The materials of the variants: ``materials`` then, for each one showing ``base`` and each atlas image, a copy
    showing the atlas; and the (len(materials), len(atlases)) int table of each copy's slot (-1: not copied)."""
    extended = list(materials)
    table = np.full((len(materials), len(atlases)), -1, dtype=np.int64)
    for m, material in enumerate(materials):
        if not any(node.image == base for node in image_textures(material)):
            continue
        for a, atlas in enumerate(atlases):
            copy = material.copy()
            copy.name = f"{material.name} ({atlas.name})"
            copy[ATLAS_TAG] = atlas
            for node in image_textures(copy):
                if node.image == base:
                    node.image = atlas
            table[m, a] = len(extended)
            extended.append(copy)
    return extended, table


def face_materials(model_materials, origin, face_atlas, table):
    """int32 (F,): the material slot of each face of a variant whose faces copy the original's faces ``origin`` (-1:
    added), which bind the atlases ``face_atlas`` (per original face, -1: the base texture)."""
    slots = np.asarray(model_materials, dtype=np.int64)
    atlas = np.where(origin >= 0, face_atlas[np.maximum(origin, 0)], -1)
    shown = (atlas >= 0) & (slots < len(table))
    copied = np.full(len(slots), -1, dtype=np.int64)
    copied[shown] = table[slots[shown], atlas[shown]]
    return np.where(copied >= 0, copied, slots).astype(np.int32)


def write_face_origin(mesh, origin):
    attr = mesh.attributes.new(FACE_ATTRIBUTE, 'INT', 'FACE')
    attr.data.foreach_set("value", np.asarray(origin, dtype=np.int32))


def remove_atlases(settings):
    """Removes the atlases of the last generation and the materials showing them, where nothing else uses them."""
    images = [item.image for item in settings.atlases if item.image is not None]
    settings.atlases.clear()
    for material in [m for m in bpy.data.materials if m.get(ATLAS_TAG) in images]:
        if material.users == 0:
            bpy.data.materials.remove(material)
    for image in images:
        if image.users == 0:
            bpy.data.images.remove(image)
