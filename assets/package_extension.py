"""Package the add-on as a Blender extension for one platform, with the engine wheel for that platform inside.

Usage: python package_extension.py --platform linux-x64 --wheels build/wheels --out dist

Writes ``<out>/worldpaint-<version>-<platform>.zip``, whose manifest claims that platform alone and lists the
bundled wheels. The release workflow (``.github/workflows/release.yml``) runs it on each platform's runner.
"""

import argparse
import fnmatch
import pathlib
import re
import shutil
import sys
import tempfile
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[1]
ADDON = ROOT / "addon" / "worldpaint"

# Blender's platform names and the wheel platform tags that install there.
PLATFORM_WHEEL_TAGS = {
    "linux-x64": ("manylinux_*_x86_64", "manylinux2014_x86_64"),
    "windows-x64": ("win_amd64",),
    "macos-arm64": ("macosx_*_arm64", "macosx_*_universal2"),
    "macos-x64": ("macosx_*_x86_64", "macosx_*_universal2"),
}


def wheel_platform_tag(name):
    """The platform tag of a wheel file name (its last dash-separated field)."""
    return name[:-len(".whl")].rsplit("-", 1)[-1]


def wheels_for(platform, wheel_dir):
    patterns = PLATFORM_WHEEL_TAGS[platform]
    return sorted(p for p in pathlib.Path(wheel_dir).glob("*.whl")
                  if any(fnmatch.fnmatch(tag, pattern) for tag in wheel_platform_tag(p.name).split(".")
                         for pattern in patterns))


def set_manifest_line(text, key, values):
    line = f"{key} = [" + ", ".join(f'"{v}"' for v in values) + "]"
    text, count = re.subn(rf"(?m)^#?\s*{key}\s*=.*$", line, text)
    return text if count else text.rstrip("\n") + "\n" + line + "\n"


def package(platform, wheel_dir, out_dir):
    wheels = wheels_for(platform, wheel_dir)
    if not wheels:
        sys.exit(f"no engine wheel for {platform} in {wheel_dir}")
    manifest_text = (ADDON / "blender_manifest.toml").read_text()
    version = re.search(r'(?m)^version\s*=\s*"([^"]+)"', manifest_text).group(1)
    with tempfile.TemporaryDirectory() as tmp:
        stage = pathlib.Path(tmp) / "worldpaint"
        shutil.copytree(ADDON, stage, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        (stage / "wheels").mkdir()
        for wheel in wheels:
            shutil.copy2(wheel, stage / "wheels" / wheel.name)
        text = set_manifest_line(manifest_text, "platforms", [platform])
        text = set_manifest_line(text, "wheels", [f"./wheels/{w.name}" for w in wheels])
        (stage / "blender_manifest.toml").write_text(text)
        out = pathlib.Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        target = out / f"worldpaint-{version}-{platform}.zip"
        with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
            for path in sorted(stage.rglob("*")):
                if path.is_file():
                    archive.write(path, path.relative_to(stage).as_posix())
    print(target)
    return target


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--platform", required=True, choices=sorted(PLATFORM_WHEEL_TAGS))
    parser.add_argument("--wheels", required=True, help="folder holding the engine wheel(s)")
    parser.add_argument("--out", required=True, help="folder the zip is written to")
    args = parser.parse_args()
    package(args.platform, args.wheels, args.out)


if __name__ == "__main__":
    main()
