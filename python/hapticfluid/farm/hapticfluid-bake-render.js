// SPDX-License-Identifier: GPL-3.0-or-later
// Flamenco job type "hapticfluid-bake-render": bake a hapticfluid scene on a GPU worker, then
// render the baked frames in chunks. With bake_chunk_size N > 0 the bake is a chain of tasks of N
// frames ("bake-1-24", "bake-25-48", ...), each depending on the one before and continuing from
// the checkpoint it left in the cache (`--until LAST`), and each render task depends on the bake
// chunk holding its frames only, so the renders of a chunk start as soon as it is baked and a
// preempted worker loses at most the chunk it was baking. 0 keeps one bake task. A job compiler script for Flamenco 3.x (written against the
// job-compiler API documented at flamenco.blender.org/usage/job-types/ for Flamenco 3.5-3.7:
// JOB_TYPE {label, settings}, compileJob(job), author.Task(name, type), author.Command(type,
// params), task.addCommand, task.addDependency, job.addTask, job.settings). Install: copy it to
// the "scripts" folder next to flamenco-manager as hapticfluid-bake-render.js, restart the Manager.
//
// Worker selection: Flamenco's worker tags apply to a whole job, so the bake task has its own
// task type, "hapticfluid-gpu": list it in the task_types of flamenco-worker.yaml on GPU workers
// only. Render tasks are type "blender" (any Blender worker). Paths in the settings are relative
// to shared_root (or absolute); shared_root may use Flamenco's two-way variables.

const JOB_TYPE = {
    label: "hapticfluid Bake + Render",
    description: "Bake a hapticfluid fluid scene (one resumable GPU task), then render the baked frames in chunks",
    settings: [
        { key: "shared_root", type: "string", subtype: "dir_path", required: true,
          description: "Shared storage root as the workers mount it" },
        { key: "scene_file", type: "string", required: true,
          description: "Scene .json or .blend, relative to shared_root" },
        { key: "cache_dir", type: "string", required: true,
          description: "Bake cache folder, relative to shared_root" },
        { key: "output_dir", type: "string", required: true,
          description: "Rendered frames folder, relative to shared_root" },
        { key: "resolution", type: "int32", default: 64, required: true,
          description: "Cells along the domain's longest edge" },
        { key: "frames", type: "string", required: true, description: "Frames to render, e.g. 1-48" },
        { key: "chunk_size", type: "int32", default: 8, description: "Frames per render task" },
        { key: "bake_chunk_size", type: "int32", default: 0,
          description: "Frames per bake task, chained (each continues from the checkpoint of the one before); 0: one bake task" },
        { key: "render_samples", type: "int32", default: 16, description: "Cycles samples per pixel" },
        { key: "render_width", type: "int32", default: 320, description: "Image width (pixels)" },
        { key: "render_height", type: "int32", default: 240, description: "Image height (pixels)" },
        { key: "python_path", type: "string", default: "",
          description: "PYTHONPATH on the workers (hapticfluid and the add-on); empty when installed" },
        { key: "python", type: "string", default: "/usr/bin/python3", description: "Python that bakes" },
        { key: "blender", type: "string", default: "{blender}", description: "Blender on the workers" },
    ],
};

const BAKE_TASK_TYPE = "hapticfluid-gpu";
const RENDER_TASK_TYPE = "blender";

// "1-48", "7" or "1-9,12-20" -> ascending contiguous runs [[first, last], ...]
function frameRuns(text) {
    const runs = [];
    for (const part of String(text).replace(/\s+/g, "").split(",")) {
        const m = /^(-?\d+)(?:-(-?\d+))?$/.exec(part);
        if (!m) throw `frames: "${part}" is not FIRST-LAST or a frame number`;
        const first = parseInt(m[1], 10);
        const last = m[2] === undefined ? first : parseInt(m[2], 10);
        if (last < first) throw `frames: "${part}" ends before it starts`;
        if (runs.length && first <= runs[runs.length - 1][1]) throw `frames: "${text}" must be ascending`;
        runs.push([first, last]);
    }
    return runs;
}

// Contiguous chunks of at most size frames, as "first-last" strings.
function frameChunks(text, size) {
    if (!(size >= 1)) throw `chunk_size must be >= 1, got ${size}`;
    const chunks = [];
    for (const [first, last] of frameRuns(text)) {
        for (let a = first; a <= last; a += size) chunks.push(`${a}-${Math.min(a + size - 1, last)}`);
    }
    return chunks;
}

// The bake's chunks over all the frames (one when size is 0 or covers them), as [first, last].
function bakeChunks(text, size) {
    if (!Number.isInteger(size) || size < 0) throw `bake_chunk_size must be 0 (one bake task) or a number of frames >= 1, got ${size}`;
    const runs = frameRuns(text);
    const first = runs[0][0], last = runs[runs.length - 1][1];
    const step = size === 0 ? last - first + 1 : size;
    const chunks = [];
    for (let a = first; a <= last; a += step) chunks.push([a, Math.min(a + step - 1, last)]);
    return chunks;
}

// The frames of `text` within first..last, as a range expression ("" when none).
function framesWithin(text, first, last) {
    const parts = [];
    for (const [a, b] of frameRuns(text)) {
        const lo = Math.max(a, first), hi = Math.min(b, last);
        if (lo <= hi) parts.push(lo === hi ? `${lo}` : `${lo}-${hi}`);
    }
    return parts.join(",");
}

// Commands run through env so that PYTHONPATH reaches Python and Blender on every worker.
function withPythonPath(settings, exe, args) {
    return author.Command("exec", { exe: "env", args: [`PYTHONPATH=${settings.python_path || ""}`, exe].concat(args) });
}

function compileJob(job) {
    const s = job.settings;
    const root = s.shared_root;
    const chunks = bakeChunks(s.frames, s.bake_chunk_size || 0);
    const chained = chunks.length > 1;

    let previous = null;
    for (const [first, last] of chunks) {
        const bake = author.Task(chained ? `bake-${first}-${last}` : "bake", BAKE_TASK_TYPE);
        bake.addCommand(withPythonPath(s, s.python || "/usr/bin/python3", [
            "-m", "hapticfluid.farm", "bake", "--root", root, "--resolution", String(s.resolution),
            "--cache", s.cache_dir, "--blender", s.blender || "{blender}", s.scene_file]
            .concat(chained ? ["--until", String(last)] : [])));
        if (previous) bake.addDependency(previous);
        job.addTask(bake);
        previous = bake;

        const frames = chained ? framesWithin(s.frames, first, last) : s.frames;
        if (!frames) continue;
        for (const chunk of frameChunks(frames, s.chunk_size || 8)) {
            const render = author.Task(`render-${chunk}`, RENDER_TASK_TYPE);
            render.addCommand(withPythonPath(s, s.blender || "{blender}", [
                "--background", "--factory-startup", "--python-use-system-env", "--python-exit-code", "1",
                "--python-expr", "import hapticfluid_blender as a; a.render_main()", "--",
                "--root", root, "--samples", String(s.render_samples || 16),
                "--size", String(s.render_width || 320), String(s.render_height || 240),
                s.cache_dir, chunk, s.output_dir]));
            render.addDependency(bake);
            job.addTask(render);
        }
    }
}
