# SPDX-License-Identifier: GPL-3.0-or-later
"""Live viewport drawing: the smoke raymarched inside the domain box, the force arrow at the
probe with its magnitude in newtons, and the haptic device's workspace as a wire box.

Draws with ``gpu``, ``gpu_extras`` and ``blf`` only (no ``bgl``), in Blender 3.4 and 4.x-5.x.
The setters only store values and run on Blender's main thread (like the draw callbacks);
the density upload to a 3D texture happens inside the draw callback, once per new array.
In ``--background`` nothing here touches ``gpu``: ``add()`` adds no handler, so nothing draws.

Units: positions in metres (world space), forces in newtons, ``density_scale`` in 1/m per unit
density (the extinction coefficient of density 1.0; Beer-Lambert: transmittance
exp(-density_scale * density * path_m)).
"""

import logging
import math
import time

import bpy
import numpy as np

from . import live_draw_geometry as geometry
from . import live_draw_gpu

log = logging.getLogger(__name__)

# Extinction of density 1.0 per metre: a 0.15 m wide plume of density 0.5 absorbs ~80% of the
# light through it, so the engine's 0..1 plume reads plainly on the default grey background.
DEFAULT_DENSITY_SCALE_PER_M = 20.0
# Domain diagonal (m) used to size the arrow before set_domain() was called.
FALLBACK_DIAGONAL_M = 1.0
LABEL_SIZE_PX = 16

_active = set()  # drawers whose handlers are added, for remove_all()


def remove_all():
    """Remove every live drawer's draw handlers and textures (the add-on's unregister)."""
    for drawer in list(_active):
        drawer.remove()


# --------------------------------------------------------------------------------------------

class LiveDrawer:
    """Draws one live session in every 3D viewport. Main thread only."""

    def __init__(self):
        self._handles = None
        self._lo = self._hi = None
        self._density = self._temperature = None
        self._dirty = False
        self._force = None                      # (origin_m, force_n, max_force_n)
        self._workspace = None                  # (lo_m, hi_m)
        # The probe the smoke's rays stop at: ("sphere", radius_local) or ("mesh", texels), its matrix_world
        self._probe = None
        self._probe_matrix = None
        self._probe_dirty = False
        self.density_scale = DEFAULT_DENSITY_SCALE_PER_M
        self.show_temperature = False
        self._temperature_ref_k = 0.0
        # GPU objects, made in the draw callback only
        self._gpu = None
        self._texture = None                    # RGBA32F 3D texture (pack_field)
        self._probe_texture = None              # RGBA32F 2D texture of the mesh probe's corners
        self._texture_has_temperature = False
        self._buffers = {}
        self._failed = False
        # counters (read by tests and stats): draw callbacks run, texture uploads done
        self.frames_drawn = 0
        self.uploads = 0
        self.sampling = None                    # "texture" or "texelFetch" once the shader is made
        self.smoke_pixel_scale = None           # fraction of the view's pixels (per axis) raymarched
        self.step_factor = 1.0                  # march step / STEP_FRACTION_OF_CELL (>= 1: fewer samples)
        self.marches = 0                        # smoke images raymarched (the rest of the redraws reuse one)
        self.march_ms = 0.0                     # wall ms of the latest timed march (software renderer)
        self._max_pixel_scale = None            # live_draw_gpu.smoke_pixel_scale(): < 1 on a software renderer
        self._occupied = None                   # occupied_cells of the uploaded density (None: no smoke)
        self._images = {}                       # region pointer -> {"offscreen", "key"}: the smoke at scale
        self._probe_source = None               # callable -> the probe's matrix_world now (drawn pose)
        self._drawn_pose = None                 # that matrix (numpy 4x4) as read in this redraw

    # ---- handlers

    def add(self):
        """Add the draw handlers to SpaceView3D (nothing in --background). Idempotent."""
        if bpy.app.background or self._handles is not None:
            return
        space = bpy.types.SpaceView3D
        self._handles = (space.draw_handler_add(self._draw_view, (), 'WINDOW', 'POST_VIEW'),
                         space.draw_handler_add(self._draw_pixel, (), 'WINDOW', 'POST_PIXEL'))
        _active.add(self)
        self._redraw()

    def remove(self):
        """Remove the draw handlers and free the GPU textures. Idempotent."""
        _active.discard(self)
        if self._handles is not None:
            space = bpy.types.SpaceView3D
            for handle in self._handles:
                space.draw_handler_remove(handle, 'WINDOW')
            self._handles = None
            self._redraw()
        self._gpu = None
        self._texture = None
        self._probe_texture = None
        self._probe_dirty = self._probe is not None
        self._images = {}
        self._buffers = {}
        if self._density is not None:
            self._dirty = True  # upload again if added again

    @property
    def is_added(self):
        return self._handles is not None

    # ---- setters (store only)

    def set_domain(self, lo_m, hi_m):
        """World box of the simulated domain: lo_m, hi_m are (x, y, z) in metres, hi above lo."""
        self._lo, self._hi = geometry.box(lo_m, hi_m, "lo_m", "hi_m")
        if self._density is not None:
            self._dirty = True  # the shadow's optical depth depends on the cell height
        self._redraw()

    def set_density(self, array_xyz_float32, temperature=None):
        """Newest density (numpy, indexed [x, y, z], any memory order, >= 0) and optionally the
        temperature in K above ambient (same shape). Uploaded at the next redraw."""
        density = np.asarray(array_xyz_float32, dtype=np.float32)
        if density.ndim != 3 or min(density.shape) < 1:
            raise ValueError(f"array_xyz_float32 must be a 3D array [x, y, z], got shape {density.shape}")
        if not np.isfinite(density).all():
            raise ValueError("array_xyz_float32 holds non-finite values")
        if temperature is not None:
            temperature = np.asarray(temperature, dtype=np.float32)
            if temperature.shape != density.shape:
                raise ValueError(f"temperature has shape {temperature.shape}, density {density.shape}")
            if not np.isfinite(temperature).all():
                raise ValueError("temperature holds non-finite values")
            # Colour ramp reference: the hottest cell (an emitter holds its temperature, so it is steady).
            self._temperature_ref_k = float(max(temperature.max(), 0.0))
        self._density, self._temperature = density, temperature
        self._dirty = True
        self._redraw()

    def set_force(self, origin_m, force_n, max_force_n):
        """Arrow from origin_m (m, world) along force_n (N, world: the force the hand feels, device
        newtons after the force gain, in world axes); max_force_n (N, > 0, the device's limit) sets
        the scale (an arrow of max_force_n is a quarter of the domain diagonal, weaker ones shorter
        on a log scale: live_draw_geometry.arrow_length_m) and the colour."""
        origin, force = geometry.vec3(origin_m, "origin_m"), geometry.vec3(force_n, "force_n")
        if not (math.isfinite(max_force_n) and max_force_n > 0.0):
            raise ValueError(f"max_force_n must be a positive number of newtons, got {max_force_n!r}")
        self._force = (origin, force, float(max_force_n))
        self._redraw()

    def set_probe(self, shape):
        """The probe the smoke stops at (drawn in front of the smoke behind it, under the smoke in
        front of it): blender_scene.probe_shape_dict's dict ({"shape": "sphere", "radius": m} or
        {"shape": "mesh", "vertices": local m, "triangles": indices}), or None (no probe)."""
        if shape is None:
            self._probe = None
        elif shape.get("shape") == "sphere":
            radius = float(shape.get("radius", -1.0))
            if not (math.isfinite(radius) and radius > 0.0):
                raise ValueError(f"shape radius must be a positive number of metres, got {shape.get('radius')!r}")
            self._probe = ("sphere", radius)
        elif shape.get("shape") == "mesh":
            texels = geometry.probe_triangle_texels(shape["vertices"], shape["triangles"])
            self._probe = ("mesh", texels, geometry.bounding_sphere(texels[:, :3]))
        else:
            raise ValueError(f"shape must be a probe shape dict ('sphere' or 'mesh'), got {shape.get('shape')!r}")
        self._probe_dirty = True
        self._redraw()

    def set_probe_matrix(self, matrix_world):
        """The probe's matrix_world (4x4 rows, m; invertible) where the smoke's rays stop."""
        m = np.asarray(matrix_world, dtype=np.float64)
        if m.shape != (4, 4) or not np.isfinite(m).all() or abs(geometry.det3(m)) < 1e-12:
            raise ValueError(f"matrix_world must be a finite invertible 4x4 matrix, got {m.tolist()!r}")
        if self._probe_matrix is None or not np.array_equal(m, self._probe_matrix):
            self._probe_matrix = m
            self._redraw()

    def set_probe_source(self, source):
        """source: a callable (main thread) returning the probe's matrix_world now (4x4 rows or a
        mathutils Matrix), or None to stop. It is read at every redraw: the force arrow, its label
        and the smoke's stop at the probe are then drawn from the pose Blender draws the probe with
        in that redraw, not from where it was at the last set_force / set_probe_matrix (which stay
        in use while source is None or returns None)."""
        if source is not None and not callable(source):
            raise ValueError(f"source must be a callable returning a 4x4 matrix or None, got {source!r}")
        self._probe_source = source
        self._redraw()

    def set_workspace_box(self, lo_m, hi_m_or_None):
        """The haptic device's workspace in the world (m) as a wire box; hi None hides it."""
        if hi_m_or_None is None or lo_m is None:
            self._workspace = None
        else:
            self._workspace = geometry.box(lo_m, hi_m_or_None, "lo_m", "hi_m_or_None")
        self._redraw()

    def set_display(self, density_scale, show_temperature):
        """density_scale: extinction (1/m) of density 1.0, >= 0; show_temperature: colour by heat."""
        if not (math.isfinite(density_scale) and density_scale >= 0.0):
            raise ValueError(f"density_scale must be >= 0 (1/m per unit density), got {density_scale!r}")
        self.density_scale = float(density_scale)
        self.show_temperature = bool(show_temperature)
        self._redraw()

    # ---- drawing (main thread, inside Blender's draw loop)

    def _redraw(self):
        """Tags the 3D views' main regions, where the smoke, arrow and label are drawn (at every
        tick through set_force): a whole area's tag would redraw its header, toolbars and sidebar
        too, each pass on a software renderer. The sidebar's figures bring their own redraws."""
        if self._handles is None:
            return
        for window in bpy.context.window_manager.windows:
            for area in window.screen.areas:
                if area.type == 'VIEW_3D':
                    for region in area.regions:
                        if region.type == 'WINDOW':
                            region.tag_redraw()

    def _diagonal(self):
        if self._lo is None:
            return FALLBACK_DIAGONAL_M
        return math.dist(self._lo, self._hi)

    def _read_drawn_pose(self):
        """The probe's matrix_world in this redraw, from the probe source (None without one)."""
        self._drawn_pose = None
        if self._probe_source is None:
            return
        try:
            m = self._probe_source()
        except ReferenceError:  # the object was deleted: the session ends at its next tick
            return
        if m is None:
            return
        m = np.asarray([list(row) for row in m], dtype=np.float64)
        if m.shape == (4, 4) and np.isfinite(m).all() and abs(geometry.det3(m)) >= 1e-12:
            self._drawn_pose = m
            self._probe_matrix = m

    def _arrow_origin(self):
        origin = self._force[0]
        if self._drawn_pose is not None:
            origin = tuple(float(c) for c in self._drawn_pose[:3, 3])
        return origin

    def _draw_view(self):
        if self._failed:
            return
        saved = live_draw_gpu.SavedState()
        try:
            self.frames_drawn += 1
            self._read_drawn_pose()
            if self._gpu is None:
                hardware_filter = live_draw_gpu.samples_linearly()
                self.sampling = "texture" if hardware_filter else "texelFetch"
                log.debug("smoke texture sampling: %s", self.sampling)
                self._max_pixel_scale = live_draw_gpu.smoke_pixel_scale()
                self.smoke_pixel_scale = self._max_pixel_scale
                self.step_factor = 1.0
                self._gpu = {
                    "hardware_filter": hardware_filter,
                    "flat": live_draw_gpu.builtin_shader('UNIFORM_COLOR', '3D_UNIFORM_COLOR'),
                    "smooth": live_draw_gpu.builtin_shader('SMOOTH_COLOR', '3D_SMOOTH_COLOR'),
                }
            self._upload()
            self._draw_smoke()
            self._draw_workspace()
            self._draw_arrow()
        except Exception:
            # Drawing must not take Blender down or spam every redraw: log once, then stop drawing.
            self._failed = True
            log.exception("hapticfluid live drawing failed and is switched off for this session")
        finally:
            saved.restore()

    def _upload(self):
        if not self._dirty or self._density is None:
            return
        cell_height = (self._hi[2] - self._lo[2]) / self._density.shape[2] if self._lo else 1.0
        packed = geometry.pack_field(self._density, self._temperature, cell_height)
        self._texture = live_draw_gpu.texture_3d(packed, self._buffers)
        self._texture_has_temperature = self._temperature is not None
        self._occupied = geometry.occupied_cells(self._density)
        self._dirty = False
        self.uploads += 1

    def _ray_shader(self, name):
        """The smoke ("volume") or composite shader for the current probe's kind (made once each)."""
        kind = live_draw_gpu.PROBE_KINDS[self._probe[0] if self._probe is not None and
                                         self._probe_matrix is not None else None]
        key = (name, kind)
        shader = self._gpu.get(key)
        if shader is None:
            if name == "volume":
                shader = live_draw_gpu.volume_shader(self._gpu["hardware_filter"], kind)
            else:
                shader = live_draw_gpu.composite_shader(kind)
            self._gpu[key] = shader
        return shader

    def _probe_uniforms(self, shader):
        """The probe's uniforms and triangle texture for _RAY_GLSL, those of the shader's probe kind
        only (the others are compiled out, and setting a missing uniform raises)."""
        from mathutils import Matrix

        if self._probe is None or self._probe_matrix is None:
            return
        m = self._probe_matrix
        if self._probe[0] == "sphere":
            shader.uniform_float("probe_sphere", (*m[:3, 3], geometry.sphere_radius_world(self._probe[1], m)))
            return
        if self._probe_dirty or self._probe_texture is None:
            self._probe_texture = live_draw_gpu.probe_texture(self._probe[1])
            self._probe_dirty = False
        shader.uniform_float("probe_inv", Matrix(m.tolist()).inverted())  # not numpy's: see geometry.det3
        shader.uniform_float("probe_params", (2.0, float(len(self._probe[1]) // 3), 0.0, 0.0))
        shader.uniform_float("probe_bound", self._probe[2])
        shader.uniform_sampler("probe_tris", self._probe_texture)

    def _draw_smoke(self):
        import gpu
        from gpu_extras.batch import batch_for_shader

        if self._texture is None or self._lo is None or self.density_scale <= 0.0 or self._occupied is None:
            return  # nothing to draw: no field, no domain, transparent smoke or no cell holding smoke
        rv3d = bpy.context.region_data
        if rv3d is None:
            return
        view_inv = rv3d.view_matrix.inverted()
        if rv3d.is_perspective:
            eye = (*view_inv.translation, 1.0)
        else:
            forward = -view_inv.col[2].xyz
            eye = (*forward, 0.0)
        hot = self.show_temperature and self._texture_has_temperature
        temp_ref = self._temperature_ref_k if hot else 0.0
        smoke_lo, smoke_hi = geometry.cells_to_world(self._occupied, self._lo, self._hi, self._density.shape)
        shader = self._ray_shader("volume")
        corners = geometry.box_corners(self._lo, self._hi)
        batch = batch_for_shader(shader, 'TRIS', {"pos": corners}, indices=geometry.BOX_TRIANGLES)

        def ray_uniforms(program):
            program.bind()
            program.uniform_float("ModelViewProjectionMatrix", rv3d.perspective_matrix)
            program.uniform_float("box_lo", (*self._lo, 0.0))
            program.uniform_float("box_hi", (*self._hi, 0.0))
            program.uniform_float("eye", eye)
            self._probe_uniforms(program)

        def march(depth_test):
            # Depth-tested against the scene where the smoke's own depth is known (see _RAY_GLSL).
            gpu.state.depth_test_set(depth_test)
            gpu.state.depth_mask_set(False)
            gpu.state.face_culling_set('FRONT')  # back faces: where each ray leaves the box
            ray_uniforms(shader)
            shader.uniform_float("params", (self.density_scale, temp_ref, self.step_factor, 0.0))
            shader.uniform_float("smoke_lo", (*smoke_lo, 0.0))
            shader.uniform_float("smoke_hi", (*smoke_hi, 0.0))
            shader.uniform_sampler("field_tex", self._texture)
            batch.draw(shader)
            gpu.state.face_culling_set('NONE')

        region = bpy.context.region
        if self._max_pixel_scale >= 1.0 or region is None:
            gpu.state.blend_set('ALPHA_PREMULT')
            march('LESS_EQUAL')
            self.marches += 1
            return
        # The software path: the smoke image at a fraction of the pixels, kept per region and
        # marched again only for new fields, another view, a moved probe or other display settings.
        image = self._smoke_image(region)
        key = (self.uploads, tuple(tuple(row) for row in rv3d.perspective_matrix), region.width, region.height,
               None if self._probe_matrix is None else self._probe_matrix.tobytes(), self.density_scale, temp_ref)
        if image["key"] != key:
            # Timed on the software renderer's threads: Blender's drawing so far is finished first
            # (a one-pixel read waits for it), so the read after the march waits for the march alone.
            gpu.state.active_framebuffer_get().read_color(0, 0, 1, 1, 4, 0, 'FLOAT')
            t0 = time.perf_counter()
            with image["offscreen"].bind():
                fb = gpu.state.active_framebuffer_get()
                fb.clear(color=(0.0, 0.0, 0.0, 0.0))
                gpu.state.blend_set('NONE')  # one back face per pixel: premultiplied colour as is
                march('NONE')  # the offscreen has no scene depth: the composite tests it
                fb.read_color(0, 0, 1, 1, 4, 0, 'FLOAT')
            image["key"] = key
            self.marches += 1
            self.march_ms = 1e3 * (time.perf_counter() - t0)
            self._adapt_budget(self.march_ms)
        composite = self._ray_shader("composite")
        faces = batch_for_shader(composite, 'TRIS', {"pos": corners}, indices=geometry.BOX_TRIANGLES)
        gpu.state.blend_set('ALPHA_PREMULT')
        gpu.state.depth_test_set('LESS_EQUAL')
        gpu.state.depth_mask_set(False)
        gpu.state.face_culling_set('FRONT')
        ray_uniforms(composite)
        composite.uniform_sampler("image", image["offscreen"].texture_color)
        faces.draw(composite)
        gpu.state.face_culling_set('NONE')

    def _smoke_image(self, region):
        """This region's smoke image, its offscreen sized to the current pixel scale."""
        import gpu

        size = (max(1, math.ceil(region.width * self.smoke_pixel_scale)),
                max(1, math.ceil(region.height * self.smoke_pixel_scale)))
        ptr = region.as_pointer()
        image = self._images.get(ptr)
        if image is None or (image["offscreen"].width, image["offscreen"].height) != size:
            if image is None and len(self._images) >= 4:  # regions come and go: keep a few
                self._images.clear()
            image = self._images[ptr] = {"offscreen": gpu.types.GPUOffScreen(*size), "key": None}
        return image

    def _adapt_budget(self, march_ms):
        """Fewer pixels while a march costs more than the budget, then fewer samples (longer steps);
        back up in the reverse order when it costs well under it."""
        budget = live_draw_gpu.SOFTWARE_SMOKE_BUDGET_MS
        lowest = live_draw_gpu.SOFTWARE_SMOKE_MIN_PIXEL_SCALE
        scale = geometry.next_pixel_scale(self.smoke_pixel_scale, march_ms, budget, lowest, self._max_pixel_scale)
        if march_ms > budget and scale <= lowest and self.smoke_pixel_scale <= lowest:
            self.step_factor = min(live_draw_gpu.SOFTWARE_SMOKE_MAX_STEP_FACTOR, self.step_factor * 1.25)
        elif march_ms < 0.5 * budget and self.step_factor > 1.0:
            self.step_factor = max(1.0, self.step_factor / 1.25)
            scale = min(scale, self.smoke_pixel_scale)  # samples come back before pixels
        self.smoke_pixel_scale = scale

    def _draw_workspace(self):
        import gpu
        from gpu_extras.batch import batch_for_shader

        if self._workspace is None:
            return
        shader = self._gpu["flat"]
        corners = geometry.box_corners(*self._workspace)
        batch = batch_for_shader(shader, 'LINES', {"pos": corners}, indices=geometry.BOX_EDGES)
        gpu.state.blend_set('ALPHA')
        gpu.state.depth_test_set('NONE')
        gpu.state.line_width_set(2.0)
        shader.bind()
        shader.uniform_float("color", (0.35, 0.75, 1.0, 0.9))
        batch.draw(shader)

    def _draw_arrow(self):
        import gpu
        from gpu_extras.batch import batch_for_shader

        if self._force is None:
            return
        _, force, max_force = self._force
        mesh = geometry.arrow_mesh(self._arrow_origin(), force, max_force, self._diagonal())
        if mesh is None:
            return
        positions, colours, _ = mesh
        shader = self._gpu["smooth"]
        batch = batch_for_shader(shader, 'TRIS', {"pos": positions, "color": colours})
        gpu.state.blend_set('NONE')
        gpu.state.depth_test_set('NONE')   # always on top: the probe is inside the smoke
        gpu.state.face_culling_set('BACK')
        shader.bind()
        batch.draw(shader)
        gpu.state.face_culling_set('NONE')

    def _draw_pixel(self):
        if self._failed or self._force is None:
            return
        import blf
        from bpy_extras.view3d_utils import location_3d_to_region_2d

        region, rv3d = bpy.context.region, bpy.context.region_data
        if region is None or rv3d is None:
            return
        _, force, max_force = self._force
        origin = self._arrow_origin()  # the pose _draw_view read in this redraw
        magnitude = math.sqrt(sum(c * c for c in force))
        mesh = geometry.arrow_mesh(origin, force, max_force, self._diagonal())
        anchor = mesh[2] if mesh is not None else origin
        xy = location_3d_to_region_2d(region, rv3d, anchor)
        if xy is None:
            return
        saved = live_draw_gpu.SavedState()
        try:
            font = 0
            scale = bpy.context.preferences.system.ui_scale
            blf.size(font, LABEL_SIZE_PX * scale)
            blf.enable(font, blf.SHADOW)
            blf.shadow(font, 3, 0.0, 0.0, 0.0, 0.9)
            blf.shadow_offset(font, 1, -1)
            r, g, b, _ = geometry.force_color(magnitude, max_force)
            blf.color(font, r, g, b, 1.0)
            blf.position(font, xy.x + 8.0 * scale, xy.y + 6.0 * scale, 0.0)
            blf.draw(font, geometry.label_text(magnitude))
            blf.disable(font, blf.SHADOW)
        finally:
            saved.restore()
