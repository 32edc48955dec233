#!/usr/bin/env python3
"""Builds the Blender add-on: the extension for Blender 4.2 and later, or the
legacy add-on zip for Blender 3.x.

    python3 blender/build.py --extension --wheel dist/asperity-….whl   # Blender 4.2+ (an extension)
    python3 blender/build.py --extension     # builds the wheel first (maturin, release)
    python3 blender/build.py                 # Blender 3.x: target/blender/asperity_addon.zip
    python3 blender/build.py --profile dev   # faster to build
    python3 blender/build.py --library target/debug/deps/lib_asperity.so   # one already built (the tests)

**The extension** (``target/blender/asperity-VERSION-PLATFORM.zip``) holds the
add-on (blender/asperity_addon), a ``blender_manifest.toml`` and, in
``wheels/``, asperity's wheel, which Blender installs into the extension's own
site-packages: Edit > Preferences > Get Extensions > Install from Disk… (or
drag the zip into Blender). The manifest's platform is the wheel's: build one
zip per platform from that platform's wheel (the release workflow's wheels).

**The legacy zip** holds the add-on and, in its vendor/ folder, asperity's
Python package with the engine compiled for this machine (the same files
`pip install ./python` installs), so Blender needs nothing else: Edit >
Preferences > Add-ons > Install… > the zip, then tick "asperity". Blender's
Python needs numpy (Blender's own builds have it; Debian's blender wants
python3-numpy). The zip is for the platform it was built on.
"""
from __future__ import annotations

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
        shutil.copy(library, pkg / ("_asperity.pyd" if library.suffix in (".dll", ".pyd") else "_asperity.abi3.so"))
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


# A wheel's platform tag → the extension platform Blender names it by.
PLATFORMS = (("manylinux", "x86_64", "linux-x64"), ("manylinux", "aarch64", "linux-arm64"),
             ("macosx", "x86_64", "macos-x64"), ("macosx", "arm64", "macos-arm64"),
             ("win", "amd64", "windows-x64"), ("win", "arm64", "windows-arm64"))


def wheel_platform(wheel: Path) -> str:
    """The Blender platform of a wheel, from its file name's platform tag."""
    tag = wheel.stem.split("-")[-1].lower()
    for system, machine, platform in PLATFORMS:
        if tag.startswith(system) and tag.endswith(machine):
            return platform
    sys.exit(f"{wheel.name}: no Blender platform for the wheel's tag {tag}")


def build_wheel() -> Path:
    """asperity's wheel for this machine (maturin, release), as docs/python.md builds it."""
    out = ROOT / "target" / "wheels"
    before = set(out.glob("asperity-*.whl"))
    subprocess.run([sys.executable, "-m", "maturin", "build", "--release", "--out", str(out)],
                   cwd=ROOT / "python", check=True)
    made = sorted(set(out.glob("asperity-*.whl")) - before) or sorted(out.glob("asperity-*.whl"))
    return made[-1]


def wheel_defaults(wheel: Path) -> dict:
    """The engine's defaults from the package inside ``wheel`` (unpacked to a scratch folder)."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        with zipfile.ZipFile(wheel) as z:
            z.extractall(d)
        library = next(Path(d, "asperity").glob("_asperity*"))
        return engine_defaults(library)


def manifest(version: str, wheel: Path, platform: str) -> str:
    """blender_manifest.toml (https://docs.blender.org/manual/en/latest/advanced/extensions/)."""
    return f"""schema_version = "1.0.0"
id = "asperity"
version = "{version}"
name = "asperity"
tagline = "Rough surfaces: rocks, growth, CA terrains, fractal IFS, patina"
maintainer = "the asperity developers"
type = "add-on"
website = "https://github.com/asperity/asperity"
tags = ["Add Mesh", "Modeling", "Material"]
blender_version_min = "4.2.0"
# asperity is MIT OR Apache-2.0 (either, at your choice), both GPL-compatible
license = ["SPDX:MIT", "SPDX:Apache-2.0"]
platforms = ["{platform}"]
wheels = ["./wheels/{wheel.name}"]

[permissions]
files = "Writes the surfaces it makes to a temporary folder while building them"
"""


def extension(wheel: Path, out: Path | None) -> Path:
    """Writes the extension zip for ``wheel``; returns its path."""
    version = wheel.name.split("-")[1]
    platform = wheel_platform(wheel)
    name = f"asperity-{version}-{platform}.zip"
    if out is None:
        out = ROOT / "target" / "blender" / name
    elif out.is_dir():
        out = out / name
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("blender_manifest.toml", manifest(version, wheel, platform))
        for f in sorted((ROOT / "blender" / "asperity_addon").glob("*.py")):
            z.write(f, f.name)
        z.writestr("engine_defaults.json", json.dumps(wheel_defaults(wheel), indent=1))
        z.write(wheel, f"wheels/{wheel.name}")
    tmp.replace(out)  # atomic: a failed build leaves the old zip
    return out


def legacy(library: Path, out: Path) -> Path:
    """Writes the Blender 3.x add-on zip with ``library`` as its engine; returns its path."""
    extension_name = "_asperity.pyd" if library.suffix in (".dll", ".pyd") else "_asperity.abi3.so"
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for f in sorted((ROOT / "blender" / "asperity_addon").glob("*.py")):
            z.write(f, f"asperity_addon/{f.name}")
        for f in sorted((ROOT / "python" / "asperity").iterdir()):
            if f.suffix in (".py", ".pyi", ".typed"):
                z.write(f, f"asperity_addon/vendor/asperity/{f.name}")
        z.write(library, f"asperity_addon/vendor/asperity/{extension_name}")
        z.writestr("asperity_addon/engine_defaults.json", json.dumps(engine_defaults(library), indent=1))
    tmp.replace(out)  # atomic: a failed build leaves the old zip
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--extension", action="store_true", help="the Blender 4.2+ extension (from a wheel)")
    parser.add_argument("--wheel", type=Path, help="with --extension: asperity's wheel (default: build one)")
    parser.add_argument("--profile", default="release", help="cargo profile of the engine (release, dev)")
    parser.add_argument("--library", type=Path, help="an engine library already built (skips cargo)")
    parser.add_argument("--out", type=Path, help="the zip to write (or a folder for it)")
    args = parser.parse_args()
    if args.extension:
        wheel = args.wheel or build_wheel()
        out = extension(wheel, args.out)
        print(f"wrote {out} ({out.stat().st_size / 1e6:.1f} MB; extension with {wheel.name})")
    else:
        library = args.library or engine_library(args.profile)
        out = legacy(library, args.out or ROOT / "target" / "blender" / "asperity_addon.zip")
        print(f"wrote {out} ({out.stat().st_size / 1e6:.1f} MB; engine from {library})")


if __name__ == "__main__":
    main()
