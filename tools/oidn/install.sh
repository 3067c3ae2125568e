#!/usr/bin/env bash
# Installs Intel Open Image Denoise (OIDN), the library behind `rayforge render --denoise` and
# `rayforge denoise`, from PyPI's `pyoidn` wheel: the wheel is downloaded with pip, checked
# against its pinned SHA-256, and its core library, CPU device and TBB (Apache-2.0, as the
# wheel's own files are MIT) are unpacked into FOLDER/lib, by default `.oidn/` at the top of
# this checkout (git-ignored), where the rayforge binary looks for them; set RAYFORGE_OIDN_DIR to
# install elsewhere, and give the binary the same variable. Debian 12 packages no OIDN in main
# (`apt-cache policy libopenimagedenoise-dev` finds none), hence the wheel.
#
# Usage: tools/oidn/install.sh            # into .oidn/ (or $RAYFORGE_OIDN_DIR)
# Needs python3 with pip and a network connection to PyPI; Linux on x86-64 (the wheel's).
set -euo pipefail

repo="$(cd "$(dirname "$0")/../.." && pwd)"
dest="${RAYFORGE_OIDN_DIR:-$repo/.oidn}"
version="2.5.1.0"
wheel="pyoidn-$version-py3-none-manylinux2014_x86_64.whl"
sha256="32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e"
# The files rayforge needs, as the wheel names them (the GPU devices are left out).
files=(
  libOpenImageDenoise.so.2.5.1
  libOpenImageDenoise_core.so.2.5.1
  libOpenImageDenoise_device_cpu.so.2.5.1
  libtbb.so.12.19
)

if [ "$(uname -s)-$(uname -m)" != "Linux-x86_64" ]; then
  echo "error: the pyoidn wheel this script installs is for Linux on x86-64, not $(uname -s)-$(uname -m);" >&2
  echo "install OIDN 2 from https://www.openimagedenoise.org/downloads.html and set RAYFORGE_OIDN_DIR to its folder" >&2
  exit 1
fi
python=python3
if ! "$python" -m pip --version >/dev/null 2>&1; then
  echo "error: $python has no pip (Debian: apt-get install python3-pip)" >&2
  exit 1
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "== downloading $wheel from PyPI"
"$python" -m pip download --quiet --no-deps --only-binary=:all: -d "$work" "pyoidn==$version"
if ! echo "$sha256  $work/$wheel" | sha256sum --check --status; then
  echo "error: $wheel does not have the SHA-256 this script pins ($sha256)" >&2
  exit 1
fi

echo "== unpacking OIDN's core, CPU device and TBB into $dest/lib"
mkdir -p "$dest/lib"
"$python" - "$work/$wheel" "$dest" "${files[@]}" <<'PY'
import shutil, sys, zipfile
wheel, dest, names = sys.argv[1], sys.argv[2], sys.argv[3:]
with zipfile.ZipFile(wheel) as z:
    for name in names:
        with z.open("pyoidn/oidn/lib/" + name) as src, open(f"{dest}/lib/{name}.part", "wb") as out:
            shutil.copyfileobj(src, out)
    with z.open("pyoidn-2.5.1.0.dist-info/licenses/LICENSE") as src, open(f"{dest}/LICENSE.pyoidn", "wb") as out:
        shutil.copyfileobj(src, out)
PY
for name in "${files[@]}"; do
  chmod 755 "$dest/lib/$name.part"
  mv -f "$dest/lib/$name.part" "$dest/lib/$name"
done
# The names the libraries ask each other for (their sonames), as links.
ln -sf libOpenImageDenoise.so.2.5.1 "$dest/lib/libOpenImageDenoise.so.2"
ln -sf libtbb.so.12.19 "$dest/lib/libtbb.so.12"

echo "== checking that the library loads and makes a CPU device"
"$python" - "$dest/lib/libOpenImageDenoise.so.2" <<'PY'
import ctypes, sys
lib = ctypes.CDLL(sys.argv[1])
lib.oidnNewDevice.restype = ctypes.c_void_p
lib.oidnCommitDevice.argtypes = [ctypes.c_void_p]
lib.oidnCommitDevice.restype = None
lib.oidnGetDeviceInt.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
lib.oidnGetDeviceError.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_char_p)]
lib.oidnReleaseDevice.argtypes = [ctypes.c_void_p]
device = lib.oidnNewDevice(1)  # OIDN_DEVICE_TYPE_CPU
message = ctypes.c_char_p()
if device:
    lib.oidnCommitDevice(device)
if not device or lib.oidnGetDeviceError(device, ctypes.byref(message)):
    sys.exit(f"error: OIDN's CPU device does not start: {message.value}")
version = lib.oidnGetDeviceInt(device, b"version")
lib.oidnReleaseDevice(device)
print(f"OIDN {version // 10000}.{version // 100 % 100}.{version % 100}, CPU device: works")
PY
echo "installed Intel Open Image Denoise in $dest/lib"
if [ "$dest" != "$repo/.oidn" ]; then
  echo "give rayforge the folder: export RAYFORGE_OIDN_DIR=$dest"
fi
