"""Model variety (Maréchal et al.): Decompose Model cuts a low-poly mesh into components and gives each a collection
holding its original piece; the user adds edited copies of the piece there (edit mode, Lattice, Simple Deform,
deleted faces); Generate Variants assembles new models from them, rejecting those with new self-intersections, into a
collection a category can paint with. When the model has texture edits (§5), Generate Variants also packs them into
atlases and each variant shows texture components picked at random, with face locking; it then makes Count variants,
repeating shapes when there are fewer."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from ..bridge import WorldPaintError, engine, variety, variety_texture
from ..props.variety import LABEL_SOURCES
from .background import BackgroundOperator
from .common import reports_errors, setting

CHOSEN_TAG = "wp_texture_edits"  # on a generated variant: the texture edits it shows (indices into the list)


def model_object(context, name):
    """The named mesh object, else the active one."""
    obj = context.scene.objects.get(name) if name else context.view_layer.objects.active
    if obj is None or obj.type != 'MESH':
        raise WorldPaintError(f"'{name}' is not a mesh object" if name else "Select the mesh to give variety to")
    return obj


def labels_of(obj):
    settings = obj.worldpaint_variety
    return variety.face_labels(obj, settings.source, settings.attribute)


def child_collection(parent, name):
    """A new collection ``name`` under ``parent`` (Blender numbers the name when it is taken)."""
    collection = bpy.data.collections.new(name)
    parent.children.link(collection)
    return collection


def remove_collection(collection):
    """Removes a collection with its objects and their meshes (the parts or variants made before)."""
    for child in list(collection.children):
        remove_collection(child)
    for obj in list(collection.objects):
        mesh = obj.data if obj.type == 'MESH' else None
        bpy.data.objects.remove(obj)
        if mesh is not None and mesh.users == 0:
            bpy.data.meshes.remove(mesh)
    bpy.data.collections.remove(collection)


def check_unchanged(obj, found, by_label):
    """An error when ``obj``'s components (``found`` by ``engine.decompose_model``) are no longer those it was
    decomposed into: a face given a new label, faces moved to another component, vertices added or removed."""
    settings = obj.worldpaint_variety
    was = [(item.label, item.faces) for item in settings.components]
    now = list(zip(found["labels"], found["faces"], strict=True))
    changed = []
    if [label for label, _ in was] != [label for label, _ in now]:
        changed.append(f"its components are labelled {', '.join(str(label) for label, _ in now)} where Decompose "
                       f"Model found {', '.join(str(label) for label, _ in was)}")
    elif was != now:
        changed += [f"its part {label} has {n} faces where it had {m}"
                    for (label, m), (_, n) in zip(was, now, strict=True) if m != n]
    else:
        for label, piece in zip(found["labels"], found["components"], strict=True):
            collection = by_label.get(label)
            piece_obj = None if collection is None else collection.get(variety.PART_TAG)
            if piece_obj is not None and piece_obj.type == 'MESH' and len(piece_obj.data.vertices) != len(
                    piece["vertices"]):
                changed.append(f"its part {label} has {len(piece['vertices'])} vertices where the piece "
                               f"'{piece_obj.name}' has {len(piece_obj.data.vertices)}")
    if changed:
        raise WorldPaintError(f"'{obj.name}' has changed since it was decomposed: {'; '.join(changed)}. Undo the "
                              "change, or click Decompose Model again (it makes new parts, removing the old ones "
                              "with their copies)")


class WORLDPAINT_OT_decompose_model(bpy.types.Operator):
    """Cut the mesh into components (by face sets, materials or a face attribute) joined by connecting regions; each
    component gets a collection with its piece, where edited copies of it become its variants"""

    bl_idname = "worldpaint.decompose_model"
    bl_label = "Decompose Model"
    bl_options = {'REGISTER', 'UNDO'}

    object: StringProperty(name="Object", description="Mesh to decompose (empty: the active object)")
    source: EnumProperty(name="Components", items=LABEL_SOURCES, default="FACE_SETS")
    attribute: StringProperty(name="Attribute", description="Integer face attribute (Components: Attribute)")
    root: IntProperty(name="Root", default=-1, min=-1,
                      description="Label of the component that stays in place (a tree's trunk); -1: the largest")

    @reports_errors
    def execute(self, context):
        obj = model_object(context, self.object)
        settings = obj.worldpaint_variety
        labels = variety.face_labels(obj, self.source, self.attribute)
        root = self.root if self.root >= 0 else None
        if root is not None and root not in labels:
            raise WorldPaintError(f"Root {root} is not the label of a component of '{obj.name}' (its labels: "
                                  f"{', '.join(str(label) for label in sorted(set(labels.tolist())))})")
        found = engine.decompose_model(variety.mesh_model(obj.data), labels, root)
        if len(found["labels"]) < 2:
            raise WorldPaintError(f"'{obj.name}' has one component only: mark at least two")

        # decomposed: now change the scene
        settings.source, settings.attribute, settings.root = self.source, self.attribute, self.root
        if settings.parts is not None:
            remove_collection(settings.parts)
        parts = child_collection(context.scene.collection, f"{obj.name} Parts")
        materials = [slot.material for slot in obj.material_slots if slot.material is not None]
        settings.components.clear()
        neighbours = {k: [] for k in range(len(found["labels"]))}
        for a, b, _n in found["regions"]:
            neighbours[a].append(found["labels"][b])
            neighbours[b].append(found["labels"][a])
        for k, (label, faces, piece) in enumerate(zip(found["labels"], found["faces"], found["components"],
                                                     strict=True)):
            collection = child_collection(parts, f"{obj.name} part {label}")
            collection[variety.COMPONENT_TAG] = label
            part = bpy.data.objects.new(f"{obj.name} part {label}",
                                        variety.part_mesh(f"{obj.name} part {label}", piece, materials))
            part.matrix_world = obj.matrix_world
            part[variety.COMPONENT_TAG] = label  # a copy (Shift+D) keeps it: where it came from
            collection[variety.PART_TAG] = part
            collection.objects.link(part)
            item = settings.components.add()
            item.name, item.label, item.faces = f"part {label}", label, faces
            item.regions = ", ".join(f"part {n}" for n in neighbours[k]) or "none"
        settings.parts = parts
        shape = "fully cyclic" if found["fully_cyclic"] else "a tree" if found["tree_like"] else "with cycles"
        settings.graph = f"{len(found['labels'])} components, {len(found['regions'])} connecting regions, {shape}"
        settings.total = "1"
        self.report({'INFO'}, f"Decomposed '{obj.name}': {settings.graph}; add edited copies of a part to its "
                              "collection to make its variants")
        return {'FINISHED'}


class WORLDPAINT_OT_generate_variants(BackgroundOperator, bpy.types.Operator):
    """Assemble new models from the parts' variants (seeded); those with new self-intersections are rejected"""

    bl_idname = "worldpaint.generate_variants"
    bl_label = "Generate Variants"
    bl_options = {'REGISTER', 'UNDO'}
    progress_text = "Generating variants"

    object: StringProperty(name="Object", description="Decomposed mesh (empty: the active object)")
    count: IntProperty(name="Count", default=50, min=1, soft_max=1000, description="Variants to generate")
    seed: IntProperty(name="Seed", default=0, min=0)
    probability: FloatProperty(name="Texture Probability", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
                               description="How likely a variant is to show each texture edit (unset: the panel's)")
    by_hand: BoolProperty(name="By Hand", default=False,
                          description="Assemble the copy each component picks (its Pick; empty: the original piece) "
                          "and add that one model to the variants")

    def _prepare(self, context):
        obj = model_object(context, self.object)
        settings = obj.worldpaint_variety
        if settings.parts is None or not settings.components:
            raise WorldPaintError(f"Decompose '{obj.name}' first")
        self._object = obj
        self._model = variety.mesh_model(obj.data)
        self._labels = labels_of(obj)
        self._root = settings.root if settings.root >= 0 else None
        found = engine.decompose_model(self._model, self._labels, self._root)
        by_label = {c.get(variety.COMPONENT_TAG): c for c in settings.parts.children}
        check_unchanged(obj, found, by_label)
        context.evaluated_depsgraph_get()  # the copies' Object Mode transforms up to date
        self._cycles = [(k, c.repeat) for k, c in enumerate(settings.components) if c.repeat > 0]
        self._variants, self._picks, self._names, self._variant_names = [], [], [], []
        self._moved = {}  # copy name -> what its Object Mode transform does, read as part of the copy
        for label, piece, item in zip(found["labels"], found["components"], settings.components, strict=True):
            collection = by_label.get(label)
            where = variety.part_path(settings.parts, collection, f"{obj.name} part {label}")
            # a copy made with Shift+D keeps the piece's custom properties: the collection names its piece
            piece_obj = None if collection is None else collection.get(variety.PART_TAG)
            edits = [] if collection is None else [o for o in collection.objects if o.type == 'MESH'
                                                  and o != piece_obj]
            reference = (piece_obj or obj).matrix_world
            models = []
            for o in edits:
                copied_from = o.get(variety.COMPONENT_TAG)
                if copied_from is not None and copied_from != label:
                    home = variety.part_path(settings.parts, by_label.get(copied_from),
                                             f"{obj.name} part {copied_from}")
                    raise WorldPaintError(f"'{o.name}' in '{where}' is a copy of the piece of '{home}' (its vertices "
                                          f"and faces are that part's): move it to '{home}'")
                relative = reference.inverted_safe() @ o.matrix_world
                moved = variety.object_mode_change(relative)
                if moved:
                    self._moved[o.name] = moved
                models.append(variety.variant_model(o, piece, where, relative if moved else None))
            self._variants.append(models)
            self._names.append(where)
            self._variant_names.append([o.name for o in edits])
            if self.by_hand and item.pick is not None and item.pick != piece_obj and item.pick not in edits:
                raise WorldPaintError(f"'{item.pick.name}' is not a copy in '{where}'")
            self._picks.append(edits.index(item.pick) + 1 if item.pick in edits else 0)
        self._texture = None
        if settings.texture_edits:
            self._texture = variety_texture.texture_inputs(obj, self._model)
            self._edit_names = [image.name for image in self._texture[2]]
        self._probability = setting(self, "probability", settings.texture_probability)

    def _compute(self, progress):
        try:
            result = engine.generate_variants(self._model, self._labels, self._variants, self.count, self.seed,
                                              root=self._root, cycles=self._cycles, progress=progress,
                                              picks=self._picks if self.by_hand else None, names=self._names,
                                              variant_names=self._variant_names)
        except engine.engine_error() as exc:
            # a copy refused for what its Object Mode transform did: say so, and how to undo it
            named = [(name, moved) for name, moved in self._moved.items() if f"copy '{name}' in" in str(exc)]
            if not named:
                raise
            name, moved = named[0]
            raise WorldPaintError(f"{exc} ('{name}' is {moved} in Object Mode, which counts as part of the copy: "
                                  "clear that with Alt+G, Alt+R or Alt+S, or edit the copy in Edit Mode)") from None
        if self._texture is not None and not self.by_hand:
            _base, base_pixels, _images, pixels = self._texture
            count = max(self.count, len(result["models"])) if result["models"] else 0
            result["texture"] = engine.texture_variety(self._model, base_pixels, pixels, count, self._probability,
                                                       self.seed, names=self._edit_names)
        return result

    def _apply(self, context, result):
        if self.by_hand:
            return self._apply_picked(context, result)
        obj = self._object
        settings = obj.worldpaint_variety
        if settings.generated is not None:
            remove_collection(settings.generated)
        variety_texture.remove_atlases(settings)
        generated = child_collection(context.scene.collection, f"{obj.name} Variants")
        materials = variety_texture.object_materials(obj)
        models, texture = result["models"], result.get("texture")
        settings.texture_report = ""
        count = len(models)
        if texture is not None:
            materials, table = self._atlases(settings, texture, materials)
            count = len(texture["face_atlas"])
        shown = [dict(models[k % len(models)]) for k in range(count)]
        origins = [result["face_origin"][k % len(models)] for k in range(count)]
        if texture is not None:
            for k, model in enumerate(shown):
                model["materials"] = variety_texture.face_materials(model["materials"], origins[k],
                                                                    texture["face_atlas"][k], table)
        variants = variety.write_variants(generated, obj.name, shown, materials)
        for k, variant in enumerate(variants):
            variety_texture.write_face_origin(variant.data, origins[k])
            if texture is not None:
                variant[CHOSEN_TAG] = [int(c) for c in texture["chosen"][k]]
        variety.hide_collection(context.scene, generated)
        settings.generated = generated
        settings.texture_probability = self._probability
        settings.total = result["total"]
        classes = [c for own in result["classes"] for c in own]
        kinds = ", ".join(f"{classes.count(k)} {k.replace('_', ' ')}" for k in sorted(set(classes))) or "none"
        shapes, made = len(result["models"]), len(variants)
        short = (f" (every one tried: {self.count} asked)" if result.get("exhausted") and made < self.count
                 else "")
        told = f"{made} variants, {shapes} shape{'s' * (shapes != 1)}" if made != shapes else f"{made} variants"
        settings.report = (f"{told} of {result['total']} possible{short}; "
                           f"{len(result['rejected'])} rejected; variants given: {kinds}; the parts take "
                           f"{result['memory']['overhead_percent']:+.0f} % of the model's memory")
        self.report({'INFO'}, f"{settings.report}. {settings.texture_report}".rstrip(". "))
        return {'FINISHED'}

    def _apply_picked(self, context, result):
        """Adds the model assembled from the picks to the variants (made when there are none)."""
        obj = self._object
        settings = obj.worldpaint_variety
        if result["rejected"]:
            reason, detail = result["rejected"][0]
            picked = ", ".join(f"'{item.pick.name}' in '{where}'" for item, where in zip(
                obj.worldpaint_variety.components, self._names, strict=True) if item.pick is not None)
            raise WorldPaintError(f"The picked copies ({picked or 'the original pieces'}) make a model whose faces "
                                  f"intersect ({reason}: {detail})")
        generated = settings.generated
        if generated is None:
            generated = child_collection(context.scene.collection, f"{obj.name} Variants")
            variety.hide_collection(context.scene, generated)
            settings.generated = generated
        made = variety.write_variants(generated, f"{obj.name} picked", result["models"],
                                      variety_texture.object_materials(obj))
        settings.total = result["total"]
        self.report({'INFO'}, f"Added '{made[0].name}' to '{generated.name}': picks {self._picks}")
        return {'FINISHED'}

    def _atlases(self, settings, texture, materials):
        """Writes the atlases as packed images, lists them in the settings and returns the variants' materials with
        the table of atlas copies (see ``variety_texture.atlas_materials``)."""
        base, _pixels, images, _edits = self._texture
        name = self._object.name
        atlases = [variety_texture.new_image(f"{name} atlas {a + 1}", rgba, base)
                   for a, rgba in enumerate(texture["images"])]
        for a, atlas in enumerate(atlases):
            item = settings.atlases.add()
            item.image = atlas
            item.edits = ", ".join(image.name for image, at in zip(images, texture["atlas_of"], strict=True) if at == a)
        shown, pairs = sum(bool(len(c)) for c in texture["chosen"]), len(texture["conflicts"])
        settings.texture_report = (
            f"{len(images)} texture edits in {texture['atlases']} atlases"
            f"{' (the fewest)' if texture['exact'] else ''}, {pairs} conflicting pair{'s' * (pairs != 1)}; "
            f"{shown} of {len(texture['chosen'])} variants show painted details")
        return variety_texture.atlas_materials(materials, base, atlases)


classes = (WORLDPAINT_OT_decompose_model, WORLDPAINT_OT_generate_variants)
