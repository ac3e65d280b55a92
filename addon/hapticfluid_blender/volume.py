"""The Volume object that shows a baked frame sequence, with a smoke material for Cycles/Eevee."""

import bpy

VOLUME_NAME = "hapticfluid Smoke"
MATERIAL_NAME = "hapticfluid Smoke"


def smoke_material(density_scale: float):
    """The shared smoke material: built once (a Principled Volume reading the 'density' grid),
    later only its density is set, so edits an artist made to it stay."""
    mat = bpy.data.materials.get(MATERIAL_NAME) or bpy.data.materials.new(MATERIAL_NAME)
    node = _principled(mat)
    if node is None:
        mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        nodes.clear()
        out = nodes.new("ShaderNodeOutputMaterial")
        out.location = (300, 0)
        node = nodes.new("ShaderNodeVolumePrincipled")
        node.location = (0, 0)
        node.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
        node.inputs["Density Attribute"].default_value = "density"
        links.new(node.outputs["Volume"], out.inputs["Volume"])
    node.inputs["Density"].default_value = density_scale
    return mat


def _principled(mat):
    if not mat.use_nodes or mat.node_tree is None:
        return None
    return next((n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeVolumePrincipled"), None)


def apply_density(obj, density_scale: float) -> None:
    """Render Density changed: the material's density and the viewport's display density follow."""
    if obj is None or obj.type != "VOLUME":
        return
    obj.data.display.density = density_scale
    for mat in obj.data.materials:
        node = _principled(mat) if mat is not None else None
        if node is not None:
            node.inputs["Density"].default_value = density_scale


def show_sequence(scene, first_file: str, frame_start: int, frame_count: int, density_scale: float,
                  existing=None, collection=None):
    """Create or update the Volume object reading ``first_file`` (the frame_start file) as a
    sequence: scene frame f shows the file numbered f. A new object goes into ``collection``
    (the active one; the scene's master collection if None). Returns the object."""
    obj = existing if existing is not None and existing.type == "VOLUME" else None
    if obj is None:
        data = bpy.data.volumes.new(VOLUME_NAME)
        obj = bpy.data.objects.new(VOLUME_NAME, data)
        (collection or scene.collection).objects.link(obj)
    vol = obj.data
    vol.filepath = first_file
    vol.is_sequence = True
    vol.frame_start = frame_start
    vol.frame_duration = frame_count
    # Blender reads file number (scene frame - frame_start + 1 + offset): offset makes it f.
    vol.frame_offset = frame_start - 1
    vol.sequence_mode = "CLIP"
    # Solid mode draws the grid times display.density; the material multiplies it by
    # density_scale: the same factor, so the viewport shows the smoke as the render does.
    vol.display.density = density_scale
    # The files carry the world transform (voxel size, origin): the object stays at identity.
    obj.matrix_world.identity()
    mat = smoke_material(density_scale)
    if vol.materials:
        vol.materials[0] = mat
    else:
        vol.materials.append(mat)
    return obj


def remove(obj):
    """Delete the Volume object (and its Volume data when nothing else uses it); None is fine."""
    if obj is None or obj.type != "VOLUME":
        return
    data = obj.data
    bpy.data.objects.remove(obj)
    if data is not None and data.users == 0:
        bpy.data.volumes.remove(data)
