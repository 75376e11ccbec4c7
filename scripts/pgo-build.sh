#!/usr/bin/env bash
# Builds `conquest` with profile-guided optimisation: an instrumented
# build explores four generated 64² fields with 16 robots, and the
# release build then lays out and inlines the code by what those runs
# did. The result is target/pgo/conquest; the plain `cargo build
# --release` is unchanged. Figures: docs/results/performance.md, stop 63.
#
# Usage: scripts/pgo-build.sh
set -euo pipefail
cd "$(dirname "$0")/.."
rustup component add llvm-tools-preview >/dev/null 2>&1 || true
profdata=$(find "$(rustc --print sysroot)" -name llvm-profdata -type f | head -n 1)
if [ -z "$profdata" ]; then
  echo "pgo-build: llvm-profdata not found (rustup component add llvm-tools-preview)" >&2
  exit 1
fi
# An explicit target keeps RUSTFLAGS off build scripts and proc macros,
# which would otherwise be instrumented too.
host=$(rustc -vV | sed -n 's/^host: //p')
work="$PWD/target/pgo"
rm -rf "$work/data"
mkdir -p "$work/data"

RUSTFLAGS="-Cprofile-generate=$work/data" CARGO_TARGET_DIR="$work/gen" \
  cargo build --release -p phone-sim --target "$host"
gen="$work/gen/$host/release/conquest"
for kind in rooms maze random open; do
  "$gen" generate "$kind" --size 64x64 --seed 2 --starts 16 --out "$work/$kind-64.field" >/dev/null
  "$gen" explore "$work/$kind-64.field" --robots 16 --json >/dev/null
done
"$profdata" merge -o "$work/conquest.profdata" "$work"/data/*.profraw

RUSTFLAGS="-Cprofile-use=$work/conquest.profdata" CARGO_TARGET_DIR="$work/use" \
  cargo build --release -p phone-sim --target "$host"
cp "$work/use/$host/release/conquest" "$work/conquest"
echo "pgo-build: $work/conquest"
