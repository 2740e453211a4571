"""The release workflow builds an extension zip for every platform the manifest may claim, with the packaging script
that `make extension` uses, so Windows and macOS users get the same extension as Linux users."""

import pathlib
import re
import sys
import tomllib
import zipfile

import yaml

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "assets"))

import package_extension  # noqa: E402

WORKFLOW = ROOT / ".github" / "workflows" / "release.yml"
# Blender's platform name -> the Rust target that builds its engine and the runner family that can build it
TARGETS = {
    "linux-x64": ("x86_64-unknown-linux-gnu", "ubuntu"),
    "windows-x64": ("x86_64-pc-windows-msvc", "windows"),
    "macos-arm64": ("aarch64-apple-darwin", "macos"),
    "macos-x64": ("x86_64-apple-darwin", "macos"),
}


def workflow_job():
    workflow = yaml.safe_load(WORKFLOW.read_text())
    return workflow["jobs"]["extension"]


def step_using(job, action):
    return next(s for s in job["steps"] if s.get("uses", "").startswith(action))


def test_every_platform_of_the_manifest_and_every_desktop_is_built():
    manifest = tomllib.loads((ROOT / "addon" / "worldpaint" / "blender_manifest.toml").read_text())
    built = {entry["platform"] for entry in workflow_job()["strategy"]["matrix"]["include"]}
    assert set(manifest["platforms"]) <= built, f"manifest {manifest['platforms']}, release {built}"
    assert built == set(TARGETS) == set(package_extension.PLATFORM_WHEEL_TAGS)


def test_each_platform_builds_its_own_target_on_a_runner_that_can():
    job = workflow_job()
    for entry in job["strategy"]["matrix"]["include"]:
        target, runner = TARGETS[entry["platform"]]
        assert entry["target"] == target, entry
        assert entry["os"].startswith(runner), entry
    makefile = (ROOT / "Makefile").read_text()
    linux = next(e for e in job["strategy"]["matrix"]["include"] if e["platform"] == "linux-x64")
    assert f"MANYLINUX := {linux['manylinux']}" in makefile, "the release and make extension target the same glibc"
    maturin = step_using(job, "PyO3/maturin-action")
    assert maturin["with"]["target"] == "${{ matrix.target }}"
    assert "--release" in maturin["with"]["args"] and "--out build/wheels" in maturin["with"]["args"]


def test_the_zips_are_packaged_by_the_script_make_extension_runs():
    job = workflow_job()
    package = next(s for s in job["steps"] if "package_extension.py" in s.get("run", ""))
    assert re.search(r"--platform \$\{\{ matrix\.platform \}\}", package["run"])
    assert "--wheels build/wheels" in package["run"] and "--out dist" in package["run"]
    assert "package_extension.py --platform linux-x64" in (ROOT / "Makefile").read_text()
    upload = step_using(job, "actions/upload-artifact")
    assert upload["with"]["path"] == "dist/worldpaint-*-${{ matrix.platform }}.zip"


def test_each_platform_zip_claims_its_platform_and_bundles_its_wheel(tmp_path):
    names = {
        "linux-x64": "worldpaint_engine-0.1.0-cp311-abi3-manylinux_2_28_x86_64.whl",
        "windows-x64": "worldpaint_engine-0.1.0-cp311-abi3-win_amd64.whl",
        "macos-arm64": "worldpaint_engine-0.1.0-cp311-abi3-macosx_11_0_arm64.whl",
        "macos-x64": "worldpaint_engine-0.1.0-cp311-abi3-macosx_10_12_x86_64.whl",
    }
    wheels = tmp_path / "wheels"
    wheels.mkdir()
    for name in names.values():  # every platform's wheel in one folder, as the release's artifacts may be
        (wheels / name).write_bytes(b"wheel of " + name.encode())
    for platform, name in names.items():
        target = package_extension.package(platform, wheels, tmp_path / "dist")
        with zipfile.ZipFile(target) as archive:
            manifest = tomllib.loads(archive.read("blender_manifest.toml").decode())
            bundled = sorted(n for n in archive.namelist() if n.startswith("wheels/"))
            assert "__init__.py" in archive.namelist()
        assert target.name.endswith(f"-{platform}.zip")
        assert manifest["platforms"] == [platform] and manifest["wheels"] == [f"./wheels/{name}"]
        assert bundled == [f"wheels/{name}"]
