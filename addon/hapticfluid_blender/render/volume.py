# SPDX-License-Identifier: GPL-3.0-or-later
"""The Volume object that shows a baked frame sequence, with a smoke material for Cycles and EEVEE
and display settings for Solid mode."""

import bpy

VOLUME_NAME = "hapticfluid Smoke"
MATERIAL_NAME = "hapticfluid Smoke"

# How a baked plume reads without tweaking (docs/ARCHITECTURE.md, "Volume display"):
# Solid mode (the workbench) draws a volume in its material's viewport display colour and lights
# it with at most a quarter of that colour, so light smoke tops out near the mid-grey of the
# default viewport background (display luminance 0.49 against 0.24) and reads grey-on-grey;
# black smoke scatters nothing and absorbs the background instead, down to 0.05. The workbench's
# display density is the render density times VIEWPORT_DENSITY_FACTOR, so thin smoke shows too.
VIEWPORT_COLOR = (0.0, 0.0, 0.0, 1.0)
VIEWPORT_DENSITY_FACTOR = 3.0
# Cycles: a light grey smoke lit by the scene's lights and world. EEVEE (Material Preview) lights
# volumes with the scene's lights only, so a plume in a scene without one, or in Material
# Preview with scene lights off, would be all but invisible: its own output adds an emission of
# EEVEE_EMISSION_PER_DENSITY times the grid's density (Blender's Emission Strength per unit of
# density), in the smoke's colour, so the plume shows wherever there is smoke and nowhere else.
SMOKE_COLOR = (0.8, 0.8, 0.8, 1.0)
EEVEE_EMISSION_PER_DENSITY = 12.0
DENSITY_GRID = "density"


def viewport_density(density_scale: float) -> float:
    """The Volume's viewport display density for a Render Density."""
    return density_scale * VIEWPORT_DENSITY_FACTOR


def _volume_shader(nodes, links, output, density_scale, location_y):
    """A Principled Volume reading the density grid, linked into `output`."""
    node = nodes.new("ShaderNodeVolumePrincipled")
    node.location = (0, location_y)
    node.inputs["Color"].default_value = SMOKE_COLOR
    node.inputs["Density Attribute"].default_value = DENSITY_GRID
    node.inputs["Density"].default_value = density_scale
    links.new(node.outputs["Volume"], output.inputs["Volume"])
    return node


def smoke_material(density_scale: float):
    """The shared smoke material: built once (a Principled Volume reading the 'density' grid for
    Cycles, another with emission by density for EEVEE, the viewport colour for Solid mode), later
    only its density is set, so edits an artist made to it stay."""
    mat = bpy.data.materials.get(MATERIAL_NAME) or bpy.data.materials.new(MATERIAL_NAME)
    if not _principled(mat):
        mat.use_nodes = True
        nodes, links = mat.node_tree.nodes, mat.node_tree.links
        nodes.clear()
        cycles_out = nodes.new("ShaderNodeOutputMaterial")
        cycles_out.location, cycles_out.target = (300, 0), "CYCLES"
        _volume_shader(nodes, links, cycles_out, density_scale, 0)
        eevee_out = nodes.new("ShaderNodeOutputMaterial")
        eevee_out.location, eevee_out.target = (300, -500), "EEVEE"
        eevee = _volume_shader(nodes, links, eevee_out, density_scale, -500)
        eevee.inputs["Emission Color"].default_value = SMOKE_COLOR
        grid = nodes.new("ShaderNodeAttribute")
        grid.location, grid.attribute_name = (-500, -700), DENSITY_GRID
        strength = nodes.new("ShaderNodeMath")
        strength.location, strength.operation = (-250, -700), "MULTIPLY"
        strength.inputs[1].default_value = EEVEE_EMISSION_PER_DENSITY
        links.new(grid.outputs["Fac"], strength.inputs[0])
        links.new(strength.outputs["Value"], eevee.inputs["Emission Strength"])
        mat.diffuse_color = VIEWPORT_COLOR  # Solid mode's colour (Material > Viewport Display)
    for node in _principled(mat):
        node.inputs["Density"].default_value = density_scale
    return mat


def _principled(mat):
    """The material's Principled Volume nodes (none when it has no node tree)."""
    if not mat.use_nodes or mat.node_tree is None:
        return []
    return [n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeVolumePrincipled"]


def apply_density(obj, density_scale: float) -> None:
    """Render Density changed: the material's density and the viewport's display density follow."""
    if obj is None or obj.type != "VOLUME":
        return
    obj.data.display.density = viewport_density(density_scale)
    for mat in obj.data.materials:
        for node in _principled(mat) if mat is not None else ():
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
    # Solid mode draws the grid times display.density (VIEWPORT_DENSITY_FACTOR above).
    vol.display.density = viewport_density(density_scale)
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
