# SPDX-License-Identifier: GPL-3.0-or-later
"""The gpu side of the live viewport drawing: GLSL, shader builders, capability probes, the
smoke texture upload and gpu.state save/restore. Only called from draw callbacks in a windowed
Blender (never in --background: GPUTexture raises there and renderer_get() crashes)."""

import numpy as np

# Raymarch step as a fraction of the smallest cell edge, and the most steps per ray.
STEP_FRACTION_OF_CELL = 0.75
MAX_STEPS = 384
# On a software renderer the smoke is raymarched at most at this fraction of the view's pixels (per
# axis) and scaled up (bilinear): smoke is soft, the arrow and box stay sharp. The drawer lowers
# the fraction down to SOFTWARE_SMOKE_MIN_PIXEL_SCALE, then lengthens the steps up to
# SOFTWARE_SMOKE_MAX_STEP_FACTOR x, while a march costs more than SOFTWARE_SMOKE_BUDGET_MS.
SOFTWARE_SMOKE_PIXEL_SCALE = 0.5
SOFTWARE_SMOKE_MIN_PIXEL_SCALE = 0.125
SOFTWARE_SMOKE_MAX_STEP_FACTOR = 2.0
SOFTWARE_SMOKE_BUDGET_MS = 20.0
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swiftshader", "software rasterizer")
# Smoke colour lit from straight above and in its own shadow (linear RGB).
SMOKE_LIT_RGB = (0.97, 0.96, 0.93)
SMOKE_SHADOW_RGB = (0.42, 0.44, 0.50)

# GLSL (Blender's create-info dialect: interface, push constants and samplers are declared in Python)

_VOLUME_VERT = """
void main()
{
  world_pos = pos;
  gl_Position = ModelViewProjectionMatrix * vec4(pos, 1.0);
}
"""

# Shared by the smoke and the composite: the eye ray through a back-face fragment, where it
# enters and leaves the box, where it first meets the probe (analytic sphere, or each triangle of
# the mesh in its local frame: probe_inv is world -> local, a ray's t is the same there), and the
# window depth of the point where the smoke along it ends. The fragment writes that depth and is
# depth-tested against the scene (LESS_EQUAL, no depth write): anything nearer than the smoke's
# end (an object in front of the domain, the probe) hides the whole ray, and the march itself stops
# at the probe, so the smoke in front of the probe is drawn over it and the probe over what is
# behind it. DEPTH_BIAS_M (towards the eye) keeps the ray that ends on the probe's surface in front
# of the probe's own rasterized depth.
_RAY_GLSL = """
void view_ray(out vec3 origin, out vec3 dir)
{
  vec3 size = box_hi.xyz - box_lo.xyz;
  if (eye.w > 0.5) {
    origin = eye.xyz;
    dir = normalize(world_pos - eye.xyz);
  }
  else {
    dir = normalize(eye.xyz);
    origin = world_pos - dir * (2.0 * length(size));
  }
}

vec2 span_of(vec3 lo, vec3 hi, vec3 origin, vec3 dir)
{
  vec3 inv = 1.0 / dir;
  vec3 t0 = (lo - origin) * inv, t1 = (hi - origin) * inv;
  vec3 tmin3 = min(t0, t1), tmax3 = max(t0, t1);
  return vec2(max(max(max(tmin3.x, tmin3.y), tmin3.z), 0.0), min(min(tmax3.x, tmax3.y), tmax3.z));
}

vec2 box_span(vec3 origin, vec3 dir)
{
  return span_of(box_lo.xyz, box_hi.xyz, origin, dir);
}

/* PROBE_KIND (0 none, 1 sphere, 2 mesh) is compiled in: a software renderer runs every branch
   of a fragment shader for all its pixels, so the mesh's triangle loop, left in a sphere's shader
   even untaken, cost ~1 CPU-s per 1280x800 redraw on llvmpipe (measured: window_test_live_pace). */
float probe_hit(vec3 origin, vec3 dir, float t_max)
{
  float best = t_max;
#if PROBE_KIND == 1
  {
    vec3 oc = origin - probe_sphere.xyz;
    float b = dot(oc, dir);
    float c = dot(oc, oc) - probe_sphere.w * probe_sphere.w;
    float h = b * b - c;
    if (h >= 0.0) {
      float t = -b - sqrt(h);
      if (t < 0.0) {
        t = -b + sqrt(h);
      }
      if (t >= 0.0 && t < best) {
        best = t;
      }
    }
  }
#endif
#if PROBE_KIND == 2
  vec3 o = (probe_inv * vec4(origin, 1.0)).xyz;
  vec3 d = mat3(probe_inv) * dir;
  /* The triangles only for rays through the mesh's bounding sphere (local frame): a software
     renderer then loops over them for the pixels near the probe only. */
  vec3 oc = o - probe_bound.xyz;
  float qa = dot(d, d), qb = dot(oc, d), qc = dot(oc, oc) - probe_bound.w * probe_bound.w;
  float qh = qb * qb - qa * qc;
  if (qh >= 0.0 && -qb + sqrt(qh) >= 0.0) {
    int n = int(probe_params.y + 0.5);
    for (int i = 0; i < n; i++) {
      vec3 a = texelFetch(probe_tris, ivec2(3 * i, 0), 0).xyz;
      vec3 e1 = texelFetch(probe_tris, ivec2(3 * i + 1, 0), 0).xyz - a;
      vec3 e2 = texelFetch(probe_tris, ivec2(3 * i + 2, 0), 0).xyz - a;
      vec3 pv = cross(d, e2);
      float det = dot(e1, pv);
      if (abs(det) < 1e-12) {
        continue;
      }
      float inv_det = 1.0 / det;
      vec3 tv = o - a;
      float u = dot(tv, pv) * inv_det;
      if (u < 0.0 || u > 1.0) {
        continue;
      }
      vec3 qv = cross(tv, e1);
      float v = dot(d, qv) * inv_det;
      if (v < 0.0 || u + v > 1.0) {
        continue;
      }
      float t = dot(e2, qv) * inv_det;
      if (t >= 0.0 && t < best) {
        best = t;
      }
    }
  }
#endif
  return best;
}

float window_depth(vec3 p)
{
  vec4 clip = ModelViewProjectionMatrix * vec4(p, 1.0);
  return clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}

/* The march's end along the ray (box exit or probe) and its biased window depth. */
float smoke_end(vec3 origin, vec3 dir, float t_in, float t_out, out float depth)
{
  float t_end = probe_hit(origin, dir, t_out);
  depth = window_depth(origin + dir * max(t_end - DEPTH_BIAS_M, t_in));
  return t_end;
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
  view_ray(origin, dir);
  vec2 span = box_span(origin, dir);
  float t_in = span.x;
  float depth;
  float t_out = smoke_end(origin, dir, span.x, span.y, depth);
  gl_FragDepth = depth;

  /* Empty-space skipping: only the ray's part inside the box of cells that hold smoke. */
  vec2 occupied = span_of(smoke_lo.xyz, smoke_hi.xyz, origin, dir);
  t_in = max(t_in, occupied.x);
  t_out = min(t_out, occupied.y);
  vec3 cell = size / vec3(textureSize(field_tex, 0));
  float dt = STEP_FRACTION * max(params.z, 1.0) * min(min(cell.x, cell.y), cell.z);
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



def builtin_shader(*names):
    """The first built-in shader that exists: names lost their '3D_' prefix in Blender 4.0."""
    import gpu

    for name in names:
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, TypeError):
            continue
    raise RuntimeError(f"none of the built-in shaders {names} exists in this Blender")


# World metres the smoke's depth is moved towards the eye (see _RAY_GLSL).
DEPTH_BIAS_M = 1e-3


def _ray_info(name, probe_kind):
    """Create-info with what _RAY_GLSL reads: the box, the eye, the probe, the back-face vertex;
    probe_kind: 0 no probe, 1 sphere, 2 mesh (PROBE_KINDS), compiled in."""
    import gpu

    iface = gpu.types.GPUStageInterfaceInfo(name)
    iface.smooth('VEC3', "world_pos")
    info = gpu.types.GPUShaderCreateInfo()
    info.push_constant('MAT4', "ModelViewProjectionMatrix")
    info.push_constant('MAT4', "probe_inv")     # probe world -> local (mesh probes)
    info.push_constant('VEC4', "box_lo")
    info.push_constant('VEC4', "box_hi")
    info.push_constant('VEC4', "eye")           # xyz: eye (w = 1, perspective) or view direction (w = 0)
    info.push_constant('VEC4', "probe_sphere")  # centre (m), radius (m)
    info.push_constant('VEC4', "probe_params")  # x: 0 no probe, 1 sphere, 2 mesh; y: mesh triangles
    info.push_constant('VEC4', "probe_bound")   # the mesh's bounding sphere, local: centre (m), radius (m)
    info.sampler(1, 'FLOAT_2D', "probe_tris")   # mesh corners (local m), 3 texels per triangle
    info.vertex_in(0, 'VEC3', "pos")
    info.vertex_out(iface)
    info.fragment_out(0, 'VEC4', "FragColor")
    # gl_FragDepth is written as plain GLSL: Blender's Python create-info has no depth-write
    # declaration up to 5.x (taken if a later one offers it). 208 bytes of push constants: above
    # Vulkan's guaranteed 128, which Blender 4.x+ prints a note about and serves from a buffer.
    if hasattr(info, "depth_write"):
        info.depth_write('ANY')
    info.define("DEPTH_BIAS_M", f"{DEPTH_BIAS_M:.6f}")
    info.define("PROBE_KIND", str(int(probe_kind)))
    return info


# The probe shapes a ray shader is compiled for (probe_params.x and PROBE_KIND).
PROBE_KINDS = {None: 0, "sphere": 1, "mesh": 2}


def volume_shader(hardware_filter=False, probe_kind=0):
    import gpu

    info = _ray_info("hapticfluid_smoke_iface", probe_kind)
    info.push_constant('VEC4', "params")   # x: extinction 1/m per unit density, y: temperature ref K,
    #                                          z: step length factor (>= 1: fewer samples per ray)
    info.push_constant('VEC4', "smoke_lo")  # the box of cells holding smoke (m): rays march only inside it
    info.push_constant('VEC4', "smoke_hi")
    info.sampler(0, 'FLOAT_3D', "field_tex")  # RGBA: density, optical depth above, temperature, 0
    info.define("MAX_STEPS", str(MAX_STEPS))
    info.define("LIT_COLOR", "vec3(%.3f, %.3f, %.3f)" % SMOKE_LIT_RGB)
    info.define("SHADOW_COLOR", "vec3(%.3f, %.3f, %.3f)" % SMOKE_SHADOW_RGB)
    info.define("STEP_FRACTION", f"{STEP_FRACTION_OF_CELL:.6f}")
    if hardware_filter:
        info.define("HARDWARE_FILTER", "1")
    info.vertex_source(_VOLUME_VERT)
    info.fragment_source(_RAY_GLSL + _VOLUME_FRAG)
    return gpu.shader.create_from_info(info)


# The software path's composite is drawn on the box's back faces too, so each fragment can test
# the depth where its own full-resolution ray's smoke ends (the march's offscreen has no scene depth).
# Bilinear by hand (texelFetch): the offscreen texture's sampler state is not ours to set either.
_COMPOSITE_FRAG = """
void main()
{
  vec3 origin, dir;
  view_ray(origin, dir);
  vec2 span = box_span(origin, dir);
  float depth;
  smoke_end(origin, dir, span.x, span.y, depth);
  gl_FragDepth = depth;
  vec4 clip = ModelViewProjectionMatrix * vec4(world_pos, 1.0);
  vec2 uv = 0.5 * clip.xy / clip.w + 0.5;
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


def composite_shader(probe_kind=0):
    import gpu

    info = _ray_info("hapticfluid_composite_iface", probe_kind)
    info.sampler(0, 'FLOAT_2D', "image")
    info.vertex_source(_VOLUME_VERT)
    info.fragment_source(_RAY_GLSL + _COMPOSITE_FRAG)
    return gpu.shader.create_from_info(info)


def probe_texture(texels):
    """A 2D RGBA32F texture (3 * triangles x 1) of live_draw_geometry.probe_triangle_texels."""
    import gpu

    flat = np.ascontiguousarray(texels, dtype=np.float32).reshape(-1)
    return gpu.types.GPUTexture((len(texels), 1), format='RGBA32F', data=gpu.types.Buffer('FLOAT', flat.size, flat))


def smoke_pixel_scale():
    """SOFTWARE_SMOKE_PIXEL_SCALE on a software renderer, else 1 (windowed Blender only: the
    renderer query crashes Blender 3.4 in --background)."""
    import gpu

    renderer = gpu.platform.renderer_get().lower()
    return SOFTWARE_SMOKE_PIXEL_SCALE if any(name in renderer for name in SOFTWARE_RENDERERS) else 1.0


def samples_linearly():
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


def texture_3d(packed, staging):
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


class SavedState:
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
