"""asperity for Blender: rough rocks, terrains, fractal surfaces and patina.

Add > Mesh > Rough Surface: subdivision rocks, berries, tentacles, mushrooms
and spurs (velho-perlin), CA terrains (peridier), DLA terrains and RDSR spheres
(kim-machiraju-thompson), IFS surfaces (poull-gentil), fBm height fields.
Object > asperity: Weather and Regions (gobron-chiba surface CA), Roughen
(subdivision detail on the object's mesh), Analyze (sidebar, asperity tab).

Every surface comes from asperity's engine through its Python package
(``engine.py``); the add-on only turns arrays into Blender data (``build.py``).
Build the extension for Blender 4.2+ with ``python3 blender/build.py
--extension`` (the manifest and asperity's wheel, which Blender installs), or
the legacy zip for Blender 3.x with ``python3 blender/build.py`` (README,
"Blender"). ``bl_info`` is for 3.x; extensions take ``blender_manifest.toml``.
"""

bl_info = {
    "name": "asperity",
    "author": "the asperity developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Add > Mesh > Rough Surface; Object > asperity; Sidebar > asperity",
    "description": "Rough surfaces from five papers: subdivision detail, growth, CA terrains, IFS, patina",
    "category": "Add Mesh",
}

import bpy  # noqa: E402

from . import operators  # noqa: E402


class AsperityPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    package_path: bpy.props.StringProperty(
        name="asperity package folder",
        description="A folder holding asperity's Python package (asperity/__init__.py), when the add-on zip "
                    "does not carry one and Blender's Python does not find it",
        subtype="DIR_PATH", default="")

    def draw(self, context):
        self.layout.prop(self, "package_path")
        try:
            from . import engine

            asp = engine.package(self.package_path)
            self.layout.label(text=f"asperity {asp.__version__} from {asp.__file__}", icon="CHECKMARK")
        except ImportError as e:
            self.layout.label(text=str(e), icon="ERROR")


class VIEW3D_MT_asperity_add(bpy.types.Menu):
    bl_idname = "VIEW3D_MT_asperity_add"
    bl_label = "Rough Surface"

    def draw(self, context):
        layout = self.layout
        layout.operator_context = "INVOKE_REGION_WIN"
        for kind in ("rock", "berry", "tentacle", "mushroom", "spur"):
            layout.operator(operators.ASPERITY_OT_add_subdivision.bl_idname, text=kind.title()).kind = kind
        layout.separator()
        for op, text in ((operators.ASPERITY_OT_add_ca_terrain, "CA Terrain"),
                         (operators.ASPERITY_OT_add_dla_terrain, "DLA Terrain"),
                         (operators.ASPERITY_OT_add_rdsr_sphere, "RDSR Sphere"),
                         (operators.ASPERITY_OT_add_ifs_surface, "IFS Surface"),
                         (operators.ASPERITY_OT_add_fbm, "fBm Height Field")):
            layout.operator(op.bl_idname, text=text)


class VIEW3D_MT_asperity_object(bpy.types.Menu):
    bl_idname = "VIEW3D_MT_asperity_object"
    bl_label = "asperity"

    def draw(self, context):
        self.layout.operator_context = "INVOKE_REGION_WIN"
        for op in operators.OBJECT_OPERATORS:
            self.layout.operator(op.bl_idname)


def _add_menu(self, context):
    self.layout.menu(VIEW3D_MT_asperity_add.bl_idname, icon="MOD_DISPLACE")


def _object_menu(self, context):
    self.layout.menu(VIEW3D_MT_asperity_object.bl_idname)


CLASSES = (AsperityPreferences, *operators.ADD_OPERATORS, *operators.OBJECT_OPERATORS,
           operators.VIEW3D_PT_asperity, VIEW3D_MT_asperity_add, VIEW3D_MT_asperity_object)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_mesh_add.append(_add_menu)
    bpy.types.VIEW3D_MT_object.append(_object_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_object_menu)
    bpy.types.VIEW3D_MT_mesh_add.remove(_add_menu)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
