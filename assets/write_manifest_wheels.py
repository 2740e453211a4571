"""Point an extension's blender_manifest.toml at the wheels bundled in its wheels/ folder.

Usage: python write_manifest_wheels.py EXTENSION_DIR
"""

import pathlib
import re
import sys


def main(extension_dir: str) -> None:
    root = pathlib.Path(extension_dir)
    wheels = sorted(p.name for p in (root / "wheels").glob("*.whl"))
    if not wheels:
        sys.exit(f"no wheel in {root / 'wheels'}")
    manifest = root / "blender_manifest.toml"
    text = manifest.read_text()
    line = "wheels = [" + ", ".join(f'"./wheels/{name}"' for name in wheels) + "]"
    text, count = re.subn(r"(?m)^#?\s*wheels\s*=.*$", line, text)
    if count == 0:
        text = text.rstrip("\n") + "\n" + line + "\n"
    manifest.write_text(text)


if __name__ == "__main__":
    main(sys.argv[1])
