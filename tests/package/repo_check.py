# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a Python that has Blender as a module (`bpy` from PyPI): the static extension repository
that scripts/build_extension.sh writes, used as an artist uses it.

    python repo_check.py REPO_DIR WORK_DIR

REPO_DIR holds one hapticfluid extension zip and the index.json that Blender's own
`server-generate` wrote for it. In one process, with Blender's user folders under WORK_DIR (new):
  - allows online access (Blender asks for it before anything is installed from a repository,
    even a local one), adds REPO_DIR as a remote repository with the Add Remote Repository
    operator (URL file://REPO_DIR/index.json, as a web server's address would be given),
    refreshes it, installs hapticfluid from it with the Install operator and enables it: the
    installed manifest's version is the published one, and `hapticfluid` imports from the
    wheel Blender unpacked and steps a small simulation (in a fresh process),
  - publishes a newer version: a copy of the zip whose manifest's patch version is one higher
    replaces the old zip, and server-generate writes the index again (what a maintainer does),
  - checks for updates (Repo Sync) and runs Upgrade All: the newer version is installed and the
    add-on is still enabled, the engine runs from the updated files, and it disables.
Exits non-zero on the first failed check.
"""

import os
import re
import subprocess
import sys
import zipfile

REPO, WORK = (os.path.abspath(a) for a in sys.argv[1:3])
HERE = os.path.dirname(os.path.abspath(__file__))
os.makedirs(WORK, exist_ok=False)
for name in ("CONFIG", "SCRIPTS", "EXTENSIONS", "DATAFILES"):  # read when bpy starts
    os.environ[f"BLENDER_USER_{name}"] = os.path.join(WORK, name.lower())
PKG_ID = "hapticfluid"


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message, flush=True)


def the_zip():
    zips = [n for n in os.listdir(REPO) if n.endswith(".zip")]
    check(len(zips) == 1 and os.path.isfile(os.path.join(REPO, "index.json")),
          f"the repository holds one zip and index.json: {sorted(os.listdir(REPO))}")
    return os.path.join(REPO, zips[0])


def manifest_version(text):
    return re.search(r'^version = "([^"]+)"', text, re.M).group(1)


def publish_newer(old_zip):
    """Rewrites the zip with the patch version one higher (the rest unchanged), replacing the old
    one in the repository, and regenerates the index with Blender's server-generate."""
    with zipfile.ZipFile(old_zip) as z:
        items = [(i, z.read(i.filename)) for i in z.infolist()]
    manifest = next(data for i, data in items if i.filename == "blender_manifest.toml").decode()
    old = manifest_version(manifest)
    major, minor, patch = (int(x) for x in old.split("."))
    new = f"{major}.{minor}.{patch + 1}"
    manifest = manifest.replace(f'version = "{old}"', f'version = "{new}"', 1)
    new_zip = os.path.join(REPO, os.path.basename(old_zip).replace(old, new))
    os.remove(old_zip)
    with zipfile.ZipFile(new_zip, "w", zipfile.ZIP_DEFLATED) as z:
        for info, data in items:
            z.writestr(info, manifest.encode() if info.filename == "blender_manifest.toml" else data)
    rc = subprocess.call([sys.executable, os.path.join(HERE, "extension_cli.py"), "server-generate", "--repo-dir", REPO])
    check(rc == 0, f"server-generate indexed {os.path.basename(new_zip)} (version {new})")
    return new


def installed_version(repo):
    with open(os.path.join(repo.directory, PKG_ID, "blender_manifest.toml"), encoding="utf-8") as f:
        return manifest_version(f.read())


ENGINE_CHECK = """
import sys, numpy as np
import hapticfluid as hf
sim = hf.Simulation(resolution=(8, 8, 8), domain_size=(1.0, 1.0, 1.0))
sim.set_smoke_source(centre=(0.5, 0.5, 0.2), radius=0.2, density=1.0, temperature=1.0)
sim.step(1 / 30)
assert np.asarray(sim.density()).max() > 0
print(hf.__version__, hf.__file__)
"""


def the_engine_runs(when):
    """A fresh process (this venv's Python, only Blender's extension site-packages added) imports
    hapticfluid from the wheel that Blender unpacked and steps an 8^3 simulation."""
    site = os.path.join(os.environ["BLENDER_USER_EXTENSIONS"], ".local", "lib",
                        f"python{sys.version_info[0]}.{sys.version_info[1]}", "site-packages")
    out = subprocess.run([sys.executable, "-c", f"import sys; sys.path.insert(0, {site!r})\n" + ENGINE_CHECK],
                         capture_output=True, text=True, cwd=WORK)
    check(out.returncode == 0 and site in out.stdout,
          f"{when}: hapticfluid from the unpacked wheel steps an 8^3 simulation: {out.stdout.strip()} {out.stderr[-800:]}")


def main():
    old_zip = the_zip()
    import bpy

    print("bpy", bpy.app.version_string, flush=True)
    prefs = bpy.context.preferences
    prefs.system.use_online_access = True  # the artist's "Allow Online Access"
    check(bpy.app.online_access, "online access is allowed")
    url = "file://" + os.path.join(REPO, "index.json")
    before = len(prefs.extensions.repos)
    result = bpy.ops.preferences.extension_repo_add(name="hapticfluid", remote_url=url, type="REMOTE")
    check(result == {"FINISHED"} and len(prefs.extensions.repos) == before + 1, f"the repository {url} is added ({result})")
    index = len(prefs.extensions.repos) - 1
    repo = prefs.extensions.repos[index]
    module = f"bl_ext.{repo.module}.{PKG_ID}"
    check(bpy.ops.extensions.repo_sync(repo_index=index) == {"FINISHED"}, f"the repository '{repo.name}' refreshes")
    result = bpy.ops.extensions.package_install(repo_index=index, pkg_id=PKG_ID, enable_on_install=True)
    check(result == {"FINISHED"} and module in prefs.addons, f"{PKG_ID} installs from it and is enabled as {module} ({result})")
    with zipfile.ZipFile(old_zip) as z:
        published = manifest_version(z.read("blender_manifest.toml").decode())
    check(installed_version(repo) == published, f"the installed version is the published {published}")
    the_engine_runs("installed")

    newer = publish_newer(old_zip)
    check(bpy.ops.extensions.repo_sync(repo_index=index) == {"FINISHED"}, "Check for Updates reads the new index")
    result = bpy.ops.extensions.package_upgrade_all(use_active_only=False)
    check(result == {"FINISHED"}, f"Install Updates finishes ({result})")
    check(installed_version(repo) == newer, f"the installed version is now {newer} (was {published})")
    check(module in prefs.addons, "the add-on is still enabled after the update")
    the_engine_runs("updated")
    bpy.ops.preferences.addon_disable(module=module)
    check(module not in prefs.addons, "the add-on disables")
    print(f"PASS repository install + upgrade {published} -> {newer} with Blender {bpy.app.version_string}", flush=True)
    if bpy.app.version[:2] == (4, 2):
        os._exit(0)  # bpy 4.2's exit handlers segfault after Python-callback properties (bpy_check.py)


if __name__ == "__main__":
    main()
