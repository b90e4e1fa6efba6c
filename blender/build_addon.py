"""Builds the Blender add-on's zip: the folder tyndall_blender/ (its
Python files and blender_manifest.toml), which Blender 4.2 to 5.0
installs with Edit → Preferences → Add-ons → Install from Disk
(bpy.ops.preferences.addon_install):

    python3 blender/build_addon.py [OUT.zip]      # default target/tyndall_blender.zip

The add-on imports Tyndall's Python package, which must be installed in
Blender's own Python (blender/README.md)."""

import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "tyndall_blender"


def build(out_path: str) -> str:
    source = os.path.join(HERE, PACKAGE)
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    with zipfile.ZipFile(out_path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name in sorted(os.listdir(source)):
            if name.endswith((".py", ".toml")):
                archive.write(os.path.join(source, name), f"{PACKAGE}/{name}")
    return out_path


if __name__ == "__main__":
    default = os.path.join(HERE, "..", "target", "tyndall_blender.zip")
    print(build(sys.argv[1] if len(sys.argv) > 1 else default))
