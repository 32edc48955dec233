#!/usr/bin/env python3
"""Builds the installable Blender add-on: target/blender/asperity_addon.zip.

    python3 blender/build.py                 # release build of the engine
    python3 blender/build.py --profile dev   # faster to build
    python3 blender/build.py --library target/debug/deps/lib_asperity.so   # one already built (the tests)

The zip holds the add-on (blender/asperity_addon) and, in its vendor/ folder,
asperity's Python package with the engine compiled for this machine (the same
files `pip install ./python` installs), so Blender needs nothing else: Edit >
Preferences > Add-ons > Install… > the zip, then tick "asperity". Blender's
Python needs numpy (Blender's own builds have it; Debian's blender wants
python3-numpy). The zip is for the platform it was built on.
"""
import argparse
import json
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def engine_library(profile: str) -> Path:
    """Builds asperity's Python extension; returns the shared library cargo made."""
    cmd = ["cargo", "build", "-p", "asperity-python", "--lib", "--profile", profile, "--message-format=json"]
    out = subprocess.run(cmd, cwd=ROOT, check=True, stdout=subprocess.PIPE, text=True).stdout
    for line in out.splitlines():
        msg = json.loads(line)
        if msg.get("reason") == "compiler-artifact" and msg["target"]["name"] == "_asperity" \
                and "cdylib" in msg["target"]["kind"]:
            return Path(next(f for f in msg["filenames"] if f.endswith((".so", ".dylib", ".dll"))))
    sys.exit("cargo built no _asperity library")


def engine_defaults(library: Path) -> dict:
    """The engine's defaults the add-on's properties take (``defaults.snapshot``),
    read from the package being bundled, loaded here from a scratch copy."""
    import importlib
    import importlib.util
    import shutil
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        pkg = Path(d) / "asperity"
        shutil.copytree(ROOT / "python" / "asperity", pkg,
                        ignore=shutil.ignore_patterns("__pycache__"))
        shutil.copy(library, pkg / ("_asperity.pyd" if library.suffix == ".dll" else "_asperity.abi3.so"))
        sys.path.insert(0, d)
        try:
            asp = importlib.import_module("asperity")
            # the add-on's module alone (its package imports bpy)
            spec = importlib.util.spec_from_file_location(
                "asperity_addon_defaults", ROOT / "blender" / "asperity_addon" / "defaults.py")
            defaults = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(defaults)
            return defaults.snapshot(asp)
        finally:
            sys.path.remove(d)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--profile", default="release", help="cargo profile of the engine (release, dev)")
    parser.add_argument("--library", type=Path, help="an engine library already built (skips cargo)")
    parser.add_argument("--out", type=Path, default=ROOT / "target" / "blender" / "asperity_addon.zip")
    args = parser.parse_args()
    library = args.library or engine_library(args.profile)
    extension = "_asperity.pyd" if library.suffix == ".dll" else "_asperity.abi3.so"
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted((ROOT / "blender" / "asperity_addon").glob("*.py")):
            z.write(f, f"asperity_addon/{f.name}")
        for f in sorted((ROOT / "python" / "asperity").iterdir()):
            if f.suffix in (".py", ".pyi", ".typed"):
                z.write(f, f"asperity_addon/vendor/asperity/{f.name}")
        z.write(library, f"asperity_addon/vendor/asperity/{extension}")
        z.writestr("asperity_addon/engine_defaults.json", json.dumps(engine_defaults(library), indent=1))
    tmp.replace(args.out)  # atomic: a failed build leaves the old zip
    print(f"wrote {args.out} ({args.out.stat().st_size / 1e6:.1f} MB; engine from {library})")


if __name__ == "__main__":
    main()
