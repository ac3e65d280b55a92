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

import bpy
import numpy as np

log = logging.getLogger(__name__)

# Extinction of density 1.0 per metre: a 0.15 m wide plume of density 0.5 absorbs ~80% of the
# light through it, so the engine's 0..1 plume reads plainly on the default grey background.
DEFAULT_DENSITY_SCALE_PER_M = 20.0
# The arrow for max_force_n is this fraction of the domain's diagonal long.
ARROW_FRACTION_OF_DIAGONAL = 0.25
# Arrows for forces above max_force_n grow up to this multiple of max_force_n, then stop growing
# (the label still shows the true magnitude).
ARROW_MAX_OVERSHOOT = 2.0
# Arrow proportions, as fractions of the max_force_n arrow's length: shaft and head radius, head length
# (the head is at most half of a short arrow, which then thins in proportion).
ARROW_SHAFT_RADIUS = 0.04
ARROW_HEAD_RADIUS = 0.1
ARROW_HEAD_LENGTH = 0.3
# Domain diagonal (m) used to size the arrow before set_domain() was called.
FALLBACK_DIAGONAL_M = 1.0
# Raymarch step as a fraction of the smallest cell edge, and the most steps per ray.
STEP_FRACTION_OF_CELL = 0.75
MAX_STEPS = 384
LABEL_SIZE_PX = 16
# On a software renderer the smoke is raymarched at this fraction of the view's pixels (per axis)
# and scaled up (bilinear): a quarter of the rays; smoke is soft, the arrow and box stay sharp.
SOFTWARE_SMOKE_PIXEL_SCALE = 0.5
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swiftshader", "software rasterizer")
# Smoke colour lit from straight above and in its own shadow (linear RGB).
SMOKE_LIT_RGB = (0.97, 0.96, 0.93)
SMOKE_SHADOW_RGB = (0.42, 0.44, 0.50)

_active = set()  # drawers whose handlers are added, for remove_all()


def remove_all():
    """Remove every live drawer's draw handlers and textures (the add-on's unregister)."""
    for drawer in list(_active):
        drawer.remove()


# --------------------------------------------------------------------------------------------
# Pure geometry and colour (no gpu: tested headless)

def _vec3(value, name):
    try:
        out = tuple(float(v) for v in value)
    except TypeError:
        raise ValueError(f"{name} must be 3 numbers (m), got {value!r}") from None
    if len(out) != 3 or not all(math.isfinite(v) for v in out):
        raise ValueError(f"{name} must be 3 finite numbers, got {value!r}")
    return out


def _box(lo_m, hi_m, lo_name, hi_name):
    lo, hi = _vec3(lo_m, lo_name), _vec3(hi_m, hi_name)
    if not all(h > l for l, h in zip(lo, hi)):
        raise ValueError(f"{hi_name} {hi} must be above {lo_name} {lo} on every axis")
    return lo, hi


def box_corners(lo, hi):
    """The 8 corners of an axis-aligned box, corner i taking hi on axis a when bit a of i is set."""
    return [tuple(hi[a] if (i >> a) & 1 else lo[a] for a in range(3)) for i in range(8)]


# Triangles of the box's 6 faces, counter-clockwise seen from outside (corner indices as above).
BOX_TRIANGLES = (
    (0, 4, 6), (0, 6, 2),  # x = lo
    (1, 3, 7), (1, 7, 5),  # x = hi
    (0, 1, 5), (0, 5, 4),  # y = lo
    (2, 6, 7), (2, 7, 3),  # y = hi
    (0, 2, 3), (0, 3, 1),  # z = lo
    (4, 5, 7), (4, 7, 6),  # z = hi
)
BOX_EDGES = tuple((i, i | (1 << a)) for i in range(8) for a in range(3) if not (i >> a) & 1)


def force_color(magnitude_n, max_force_n):
    """Green at zero, yellow at half of max_force_n, red from max_force_n up (RGBA)."""
    x = min(max(magnitude_n / max_force_n, 0.0), 1.0)
    if x < 0.5:
        return (0.25 + 1.5 * x, 0.9, 0.2, 1.0)
    return (1.0, 0.9 - 1.6 * (x - 0.5), 0.2 - 0.3 * (x - 0.5), 1.0)


def arrow_length_m(magnitude_n, max_force_n, diagonal_m):
    """Arrow length: max_force_n is ARROW_FRACTION_OF_DIAGONAL of the diagonal, linear below, capped."""
    scale = ARROW_FRACTION_OF_DIAGONAL * diagonal_m / max_force_n
    return scale * min(magnitude_n, ARROW_MAX_OVERSHOOT * max_force_n)


def arrow_mesh(origin, force, max_force_n, diagonal_m, sides=12):
    """Triangles of a shaded 3D arrow from origin along force: (positions, colours, head point).

    None when the force is too small to draw. Arrows longer than twice the head keep the thickness
    of the max_force_n arrow; shorter ones are scaled-down copies of that shape (a cone on a stub).
    Triangles are counter-clockwise from outside.
    """
    from mathutils import Vector

    f = Vector(force)
    magnitude = f.length
    length = arrow_length_m(magnitude, max_force_n, diagonal_m)
    ref = ARROW_FRACTION_OF_DIAGONAL * diagonal_m
    if length < 1e-4 * ref:
        return None
    axis = f / magnitude
    head_len = min(ARROW_HEAD_LENGTH * ref, 0.5 * length)
    thickness = ref * head_len / (ARROW_HEAD_LENGTH * ref)  # a short arrow is a scaled-down one, not a disc
    head_r, shaft_r = ARROW_HEAD_RADIUS * thickness, ARROW_SHAFT_RADIUS * thickness
    o = Vector(origin)
    tip = o + axis * length
    neck = tip - axis * head_len
    u = axis.orthogonal().normalized()
    v = axis.cross(u)
    ring = [u * math.cos(2 * math.pi * k / sides) + v * math.sin(2 * math.pi * k / sides) for k in range(sides)]
    base = force_color(magnitude, max_force_n)
    light = Vector((0.35, -0.45, 0.82)).normalized()

    positions, colours = [], []

    def tri(a, b, c, normal):
        shade = 0.45 + 0.55 * max(normal.dot(light), 0.0)
        rgba = (base[0] * shade, base[1] * shade, base[2] * shade, 1.0)
        positions.extend((tuple(a), tuple(b), tuple(c)))
        colours.extend((rgba, rgba, rgba))

    for k in range(sides):
        r0, r1 = ring[k], ring[(k + 1) % sides]
        mid = (r0 + r1).normalized()
        a0, a1 = o + r0 * shaft_r, o + r1 * shaft_r
        b0, b1 = neck + r0 * shaft_r, neck + r1 * shaft_r
        tri(a0, a1, b1, mid)                                     # shaft side
        tri(a0, b1, b0, mid)
        tri(o, a1, a0, -axis)                                    # shaft cap
        c0, c1 = neck + r0 * head_r, neck + r1 * head_r
        slant = (mid * head_len + axis * head_r).normalized()
        tri(c0, c1, tip, slant)                                  # cone
        tri(neck, c1, c0, -axis)                                 # cone base
    return positions, colours, tuple(tip)


def label_text(magnitude_n):
    """The force label: '3.2 N'; two decimals below 1 N ('0.45 N')."""
    return f"{magnitude_n:.2f} N" if magnitude_n < 1.0 else f"{magnitude_n:.1f} N"


# --------------------------------------------------------------------------------------------
# GLSL (Blender's create-info dialect: interface, push constants and samplers are declared in Python)

_VOLUME_VERT = """
void main()
{
  world_pos = pos;
  gl_Position = ModelViewProjectionMatrix * vec4(pos, 1.0);
}
"""

# Drawn on the box's back faces: each fragment is where its eye ray leaves the box. The ray is
# marched from where it enters (or from the eye, inside the box) with jittered steps; the field is
# interpolated trilinearly by texture() where this Blender's sampler filters linearly (probed once,
# 2.3x faster on llvmpipe), by hand from 8 texelFetch otherwise (HARDWARE_FILTER undefined). Light
# comes from straight above: the optical depth above each cell is summed on the CPU at upload (one
# fetch per step gives the self-shadowing); temperature (optional) tints with a black-body-like ramp.
_VOLUME_FRAG = """
vec4 fetch_trilinear(vec3 uvw)
{
#ifdef HARDWARE_FILTER
  return texture(field_tex, uvw);
#endif
  ivec3 n = textureSize(field_tex, 0);
  vec3 g = clamp(uvw, 0.0, 1.0) * vec3(n) - 0.5;
  vec3 f = fract(g);
  ivec3 a = clamp(ivec3(floor(g)), ivec3(0), n - 1);
  ivec3 b = min(a + 1, n - 1);
  vec4 x00 = mix(texelFetch(field_tex, a, 0), texelFetch(field_tex, ivec3(b.x, a.y, a.z), 0), f.x);
  vec4 x10 = mix(texelFetch(field_tex, ivec3(a.x, b.y, a.z), 0), texelFetch(field_tex, ivec3(b.x, b.y, a.z), 0), f.x);
  vec4 x01 = mix(texelFetch(field_tex, ivec3(a.x, a.y, b.z), 0), texelFetch(field_tex, ivec3(b.x, a.y, b.z), 0), f.x);
  vec4 x11 = mix(texelFetch(field_tex, ivec3(a.x, b.y, b.z), 0), texelFetch(field_tex, b, 0), f.x);
  return mix(mix(x00, x10, f.y), mix(x01, x11, f.y), f.z);
}

vec3 heat_ramp(float t)
{
  t = clamp(t, 0.0, 1.0);
  return vec3(smoothstep(0.0, 0.35, t), smoothstep(0.25, 0.75, t), smoothstep(0.6, 1.0, t)) * 1.6;
}

void main()
{
  vec3 lo = box_lo.xyz, hi = box_hi.xyz, size = hi - lo;
  vec3 dir, origin;
  if (eye.w > 0.5) {
    origin = eye.xyz;
    dir = normalize(world_pos - eye.xyz);
  }
  else {
    dir = normalize(eye.xyz);
    origin = world_pos - dir * (2.0 * length(size));
  }
  vec3 inv = 1.0 / dir;
  vec3 t0 = (lo - origin) * inv, t1 = (hi - origin) * inv;
  vec3 tmin3 = min(t0, t1), tmax3 = max(t0, t1);
  float t_in = max(max(max(tmin3.x, tmin3.y), tmin3.z), 0.0);
  float t_out = min(min(tmax3.x, tmax3.y), tmax3.z);

  vec3 cell = size / vec3(textureSize(field_tex, 0));
  float dt = STEP_FRACTION * min(min(cell.x, cell.y), cell.z);
  float jitter = fract(sin(dot(gl_FragCoord.xy, vec2(12.9898, 78.233))) * 43758.5453);
  float t = t_in + jitter * dt;
  float sigma = params.x;
  float temp_ref = params.y;

  float trans = 1.0;
  vec3 color = vec3(0.0);
  for (int i = 0; i < MAX_STEPS && t < t_out; i++, t += dt) {
    vec3 p = origin + dir * t;
    /* x: density, y: optical depth above (density * m), z: temperature (K above ambient) */
    vec4 s = fetch_trilinear((p - lo) / size);
    if (s.x <= 1e-4) {
      continue;
    }
    float alpha = 1.0 - exp(-sigma * s.x * dt);
    float lit = exp(-sigma * s.y);
    vec3 c = mix(SHADOW_COLOR, LIT_COLOR, lit);
    if (temp_ref > 0.0) {
      float heat = s.z / temp_ref;
      c = mix(c, heat_ramp(heat), clamp(heat * 1.5, 0.0, 1.0));
    }
    color += trans * alpha * c;
    trans *= 1.0 - alpha;
    if (trans < 0.01) {
      break;
    }
  }
  FragColor = vec4(color, 1.0 - trans);
}
"""



def _builtin_shader(*names):
    """The first built-in shader that exists: names lost their '3D_' prefix in Blender 4.0."""
    import gpu

    for name in names:
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, TypeError):
            continue
    raise RuntimeError(f"none of the built-in shaders {names} exists in this Blender")


def _volume_shader(hardware_filter=False):
    import gpu

    iface = gpu.types.GPUStageInterfaceInfo("hapticfluid_smoke_iface")
    iface.smooth('VEC3', "world_pos")
    info = gpu.types.GPUShaderCreateInfo()
    info.push_constant('MAT4', "ModelViewProjectionMatrix")
    info.push_constant('VEC4', "box_lo")
    info.push_constant('VEC4', "box_hi")
    info.push_constant('VEC4', "eye")      # xyz: eye (w = 1, perspective) or view direction (w = 0)
    info.push_constant('VEC4', "params")   # x: extinction 1/m per unit density, y: temperature ref K
    info.sampler(0, 'FLOAT_3D', "field_tex")  # RGBA: density, optical depth above, temperature, 0
    info.vertex_in(0, 'VEC3', "pos")
    info.vertex_out(iface)
    info.fragment_out(0, 'VEC4', "FragColor")
    info.define("MAX_STEPS", str(MAX_STEPS))
    info.define("LIT_COLOR", "vec3(%.3f, %.3f, %.3f)" % SMOKE_LIT_RGB)
    info.define("SHADOW_COLOR", "vec3(%.3f, %.3f, %.3f)" % SMOKE_SHADOW_RGB)
    info.define("STEP_FRACTION", f"{STEP_FRACTION_OF_CELL:.6f}")
    if hardware_filter:
        info.define("HARDWARE_FILTER", "1")
    info.vertex_source(_VOLUME_VERT)
    info.fragment_source(_VOLUME_FRAG)
    return gpu.shader.create_from_info(info)


def optical_depth_above(density, cell_height_m):
    """Density integrated from each cell's centre up to the domain's top (density * m), [x, y, z]:
    the light from straight above reaches cell k through half of it and all cells above."""
    above = np.cumsum(density[:, :, ::-1], axis=2, dtype=np.float64)[:, :, ::-1]
    return ((above - 0.5 * density) * cell_height_m).astype(np.float32)


def pack_field(density, temperature, cell_height_m):
    """The smoke texture's texels, (z, y, x, 4) C order = x fastest, RGBA per texel: density,
    optical depth above, temperature (0 when None), 0."""
    nx, ny, nz = density.shape
    packed = np.zeros((nz, ny, nx, 4), dtype=np.float32)
    packed[..., 0] = density.transpose(2, 1, 0)
    packed[..., 1] = optical_depth_above(density, cell_height_m).transpose(2, 1, 0)
    if temperature is not None:
        packed[..., 2] = temperature.transpose(2, 1, 0)
    return packed


_COMPOSITE_VERT = """
void main()
{
  uv = pos * 0.5 + 0.5;
  gl_Position = vec4(pos, 0.0, 1.0);
}
"""

# Bilinear by hand (texelFetch): the offscreen texture's sampler state is not ours to set either.
_COMPOSITE_FRAG = """
void main()
{
  ivec2 n = textureSize(image, 0);
  vec2 g = uv * vec2(n) - 0.5;
  vec2 f = fract(g);
  ivec2 a = clamp(ivec2(floor(g)), ivec2(0), n - 1);
  ivec2 b = min(a + 1, n - 1);
  vec4 bottom = mix(texelFetch(image, a, 0), texelFetch(image, ivec2(b.x, a.y), 0), f.x);
  vec4 top = mix(texelFetch(image, ivec2(a.x, b.y), 0), texelFetch(image, b, 0), f.x);
  FragColor = mix(bottom, top, f.y);
}
"""


def _composite_shader():
    import gpu

    iface = gpu.types.GPUStageInterfaceInfo("hapticfluid_composite_iface")
    iface.smooth('VEC2', "uv")
    info = gpu.types.GPUShaderCreateInfo()
    info.sampler(0, 'FLOAT_2D', "image")
    info.vertex_in(0, 'VEC2', "pos")
    info.vertex_out(iface)
    info.fragment_out(0, 'VEC4', "FragColor")
    info.vertex_source(_COMPOSITE_VERT)
    info.fragment_source(_COMPOSITE_FRAG)
    return gpu.shader.create_from_info(info)


def _smoke_pixel_scale():
    """SOFTWARE_SMOKE_PIXEL_SCALE on a software renderer, else 1 (windowed Blender only: the
    renderer query crashes Blender 3.4 in --background)."""
    import gpu

    renderer = gpu.platform.renderer_get().lower()
    return SOFTWARE_SMOKE_PIXEL_SCALE if any(name in renderer for name in SOFTWARE_RENDERERS) else 1.0


def _samples_linearly():
    """Whether texture() on a Python-made 3D texture filters linearly here (it does in Blender 3.4;
    the sampler state of such textures is not settable from Python and has changed between
    versions): one texel drawn into a 1x1 offscreen between a 0 and a 1 texel reads 0.5 if so."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    tex = gpu.types.GPUTexture((2, 1, 1), format='RGBA32F',
                               data=gpu.types.Buffer('FLOAT', 8, [0.0] * 4 + [1.0] * 4))
    info = gpu.types.GPUShaderCreateInfo()
    info.sampler(0, 'FLOAT_3D', "field_tex")
    info.vertex_in(0, 'VEC2', "pos")
    info.fragment_out(0, 'VEC4', "FragColor")
    info.vertex_source("void main() { gl_Position = vec4(pos, 0.0, 1.0); }")
    info.fragment_source("void main() { FragColor = texture(field_tex, vec3(0.5)); }")
    shader = gpu.shader.create_from_info(info)
    batch = batch_for_shader(shader, 'TRI_FAN', {"pos": [(-1, -1), (1, -1), (1, 1), (-1, 1)]})
    offscreen = gpu.types.GPUOffScreen(1, 1)
    try:
        with offscreen.bind():
            fb = gpu.state.active_framebuffer_get()
            fb.clear(color=(0.0, 0.0, 0.0, 0.0))
            gpu.state.blend_set('NONE')
            shader.bind()
            shader.uniform_sampler("field_tex", tex)
            batch.draw(shader)
            value = fb.read_color(0, 0, 1, 1, 4, 0, 'FLOAT')[0][0][0]
    finally:
        offscreen.free()
    return 0.25 < value < 0.75


def _texture_3d(packed, staging):
    """A new RGBA32F 3D texture from pack_field()'s array; the staging Buffer is reused."""
    import gpu

    nz, ny, nx, _ = packed.shape
    flat = packed.reshape(-1)
    buf = staging.get("buffer")
    if buf is None or len(buf) != flat.size:
        buf = gpu.types.Buffer('FLOAT', flat.size)
        staging["buffer"] = buf
    try:
        np.frombuffer(buf, dtype=np.float32)[:] = flat
    except (TypeError, ValueError, BufferError):  # a Buffer without the buffer protocol
        buf = gpu.types.Buffer('FLOAT', flat.size, flat)
        staging["buffer"] = buf
    return gpu.types.GPUTexture((nx, ny, nz), format='RGBA32F', data=buf)


class _SavedState:
    """gpu.state as a draw callback found it; restore() puts it back."""

    def __init__(self):
        import gpu

        self.blend = gpu.state.blend_get()
        self.depth_test = gpu.state.depth_test_get()
        self.depth_mask = gpu.state.depth_mask_get()
        self.line_width = gpu.state.line_width_get()

    def restore(self):
        import gpu

        gpu.state.blend_set(self.blend)
        gpu.state.depth_test_set(self.depth_test)
        gpu.state.depth_mask_set(self.depth_mask)
        gpu.state.line_width_set(self.line_width)
        gpu.state.face_culling_set('NONE')  # no getter; 'NONE' is what draw callbacks get


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
        self.density_scale = DEFAULT_DENSITY_SCALE_PER_M
        self.show_temperature = False
        self._temperature_ref_k = 0.0
        # GPU objects, made in the draw callback only
        self._gpu = None
        self._texture = None                    # RGBA32F 3D texture (pack_field)
        self._texture_has_temperature = False
        self._buffers = {}
        self._failed = False
        # counters (read by tests and stats): draw callbacks run, texture uploads done
        self.frames_drawn = 0
        self.uploads = 0
        self.sampling = None                    # "texture" or "texelFetch" once the shader is made
        self.smoke_pixel_scale = None           # fraction of the view's pixels (per axis) raymarched
        self._offscreens = {}                   # (width, height) -> GPUOffScreen of the smoke at that scale

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
        self._offscreens = {}
        self._buffers = {}
        if self._density is not None:
            self._dirty = True  # upload again if added again

    @property
    def is_added(self):
        return self._handles is not None

    # ---- setters (store only)

    def set_domain(self, lo_m, hi_m):
        """World box of the simulated domain: lo_m, hi_m are (x, y, z) in metres, hi above lo."""
        self._lo, self._hi = _box(lo_m, hi_m, "lo_m", "hi_m")
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
        """Arrow from origin_m (m, world) along force_n (N, world); max_force_n (N, > 0) sets the
        scale (an arrow of max_force_n is a quarter of the domain diagonal) and the colour."""
        origin, force = _vec3(origin_m, "origin_m"), _vec3(force_n, "force_n")
        if not (math.isfinite(max_force_n) and max_force_n > 0.0):
            raise ValueError(f"max_force_n must be a positive number of newtons, got {max_force_n!r}")
        self._force = (origin, force, float(max_force_n))
        self._redraw()

    def set_workspace_box(self, lo_m, hi_m_or_None):
        """The haptic device's workspace in the world (m) as a wire box; hi None hides it."""
        if hi_m_or_None is None or lo_m is None:
            self._workspace = None
        else:
            self._workspace = _box(lo_m, hi_m_or_None, "lo_m", "hi_m_or_None")
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
        if self._handles is None:
            return
        for window in bpy.context.window_manager.windows:
            for area in window.screen.areas:
                if area.type == 'VIEW_3D':
                    area.tag_redraw()

    def _diagonal(self):
        if self._lo is None:
            return FALLBACK_DIAGONAL_M
        return math.dist(self._lo, self._hi)

    def _draw_view(self):
        if self._failed:
            return
        saved = _SavedState()
        try:
            self.frames_drawn += 1
            if self._gpu is None:
                hardware_filter = _samples_linearly()
                self.sampling = "texture" if hardware_filter else "texelFetch"
                log.debug("smoke texture sampling: %s", self.sampling)
                self.smoke_pixel_scale = _smoke_pixel_scale()
                self._gpu = {
                    "volume": _volume_shader(hardware_filter),
                    "composite": _composite_shader(),
                    "flat": _builtin_shader('UNIFORM_COLOR', '3D_UNIFORM_COLOR'),
                    "smooth": _builtin_shader('SMOOTH_COLOR', '3D_SMOOTH_COLOR'),
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
        packed = pack_field(self._density, self._temperature, cell_height)
        self._texture = _texture_3d(packed, self._buffers)
        self._texture_has_temperature = self._temperature is not None
        self._dirty = False
        self.uploads += 1

    def _draw_smoke(self):
        import gpu
        from gpu_extras.batch import batch_for_shader

        if self._texture is None or self._lo is None or self.density_scale <= 0.0:
            return
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
        shader = self._gpu["volume"]
        corners = box_corners(self._lo, self._hi)
        batch = batch_for_shader(shader, 'TRIS', {"pos": corners}, indices=BOX_TRIANGLES)

        def march():
            gpu.state.depth_test_set('NONE')
            gpu.state.depth_mask_set(False)
            gpu.state.face_culling_set('FRONT')  # back faces: where each ray leaves the box
            shader.bind()
            shader.uniform_float("ModelViewProjectionMatrix", rv3d.perspective_matrix)
            shader.uniform_float("box_lo", (*self._lo, 0.0))
            shader.uniform_float("box_hi", (*self._hi, 0.0))
            shader.uniform_float("eye", eye)
            shader.uniform_float("params", (self.density_scale, temp_ref, 0.0, 0.0))
            shader.uniform_sampler("field_tex", self._texture)
            batch.draw(shader)
            gpu.state.face_culling_set('NONE')

        region = bpy.context.region
        if self.smoke_pixel_scale >= 1.0 or region is None:
            gpu.state.blend_set('ALPHA_PREMULT')
            march()
            return
        size = (max(1, math.ceil(region.width * self.smoke_pixel_scale)),
                max(1, math.ceil(region.height * self.smoke_pixel_scale)))
        offscreen = self._offscreens.get(size)  # one per view size: several viewports do not thrash
        if offscreen is None:
            if len(self._offscreens) >= 4:
                self._offscreens.clear()
            offscreen = self._offscreens[size] = gpu.types.GPUOffScreen(*size)
        with offscreen.bind():
            gpu.state.active_framebuffer_get().clear(color=(0.0, 0.0, 0.0, 0.0))
            gpu.state.blend_set('NONE')  # one back face per pixel: premultiplied colour as is
            march()
        composite = self._gpu["composite"]
        quad = batch_for_shader(composite, 'TRI_FAN', {"pos": ((-1, -1), (1, -1), (1, 1), (-1, 1))})
        gpu.state.blend_set('ALPHA_PREMULT')
        gpu.state.depth_test_set('NONE')
        composite.bind()
        composite.uniform_sampler("image", offscreen.texture_color)
        quad.draw(composite)

    def _draw_workspace(self):
        import gpu
        from gpu_extras.batch import batch_for_shader

        if self._workspace is None:
            return
        shader = self._gpu["flat"]
        batch = batch_for_shader(shader, 'LINES', {"pos": box_corners(*self._workspace)}, indices=BOX_EDGES)
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
        origin, force, max_force = self._force
        mesh = arrow_mesh(origin, force, max_force, self._diagonal())
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
        origin, force, max_force = self._force
        magnitude = math.sqrt(sum(c * c for c in force))
        mesh = arrow_mesh(origin, force, max_force, self._diagonal())
        anchor = mesh[2] if mesh is not None else origin
        xy = location_3d_to_region_2d(region, rv3d, anchor)
        if xy is None:
            return
        saved = _SavedState()
        try:
            font = 0
            scale = bpy.context.preferences.system.ui_scale
            blf.size(font, LABEL_SIZE_PX * scale)
            blf.enable(font, blf.SHADOW)
            blf.shadow(font, 3, 0.0, 0.0, 0.0, 0.9)
            blf.shadow_offset(font, 1, -1)
            r, g, b, _ = force_color(magnitude, max_force)
            blf.color(font, r, g, b, 1.0)
            blf.position(font, xy.x + 8.0 * scale, xy.y + 6.0 * scale, 0.0)
            blf.draw(font, label_text(magnitude))
            blf.disable(font, blf.SHADOW)
        finally:
            saved.restore()
