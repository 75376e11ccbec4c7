#!/usr/bin/env bash
# CI for the e-puck2 firmware (called from the project's .ci/run).
#
# 1. installs what it needs: the thumbv7em-none-eabihf target, flip-link,
#    qemu-system-arm (apt, only when missing);
# 2. checks formatting; builds the real firmware and the QEMU variant in
#    release, failing on any warning; clippy with warnings denied;
# 3. prints the size report and fails over budget (flash 128 KiB, static
#    RAM 48 KiB);
# 4. runs the host unit tests (drivers-logic, host-tests) and the QEMU
#    end-to-end tests, under a timeout;
# 5. runs a complete exploration by two emulated robots (the real firmware
#    in QEMU, simulated bodies attached by `conquest explore --qemu 2`) and
#    fails unless the report says complete.
#
# Environment: CARGO_BUILD_JOBS (default 2), CARGO_TARGET_DIR (default
# ./target), FIRMWARE_CI_TIMEOUT (seconds for the test step, default 300),
# FIRMWARE_EXPLORE_TIMEOUT (seconds for the emulated exploration, default 300).
# The ELFs end up in $CARGO_TARGET_DIR/firmware-{epuck2,qemu}.elf.
set -euo pipefail
cd "$(dirname "$0")"

t0=$(date +%s)
step() { echo "== firmware-rtic: $* (+$(( $(date +%s) - t0 ))s)"; }
jobs="${CARGO_BUILD_JOBS:-2}"
tdir="${CARGO_TARGET_DIR:-target}"
host=x86_64-unknown-linux-gnu

step "tools"
if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
  rustup target add thumbv7em-none-eabihf
fi
if ! command -v flip-link >/dev/null; then
  if ! cargo install flip-link --locked; then
    # Stack-overflow protection is not worth a red CI: link with the
    # toolchain's rust-lld (what flip-link wraps) and say so.
    echo "firmware-rtic: flip-link unavailable, linking with rust-lld" >&2
    export CARGO_TARGET_THUMBV7EM_NONE_EABIHF_LINKER=rust-lld
  fi
fi
if ! command -v qemu-system-arm >/dev/null; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq qemu-system-arm
fi

# Builds with the given cargo arguments; fails if the compiler warned about
# any crate of this workspace (registry crates' warnings are capped by cargo).
build_no_warnings() {
  local log
  log=$(mktemp)
  if ! cargo build --release -j "$jobs" "$@" 2>&1 | tee "$log"; then
    rm -f "$log"
    return 1
  fi
  if grep -q '^warning' "$log"; then
    echo "firmware-rtic: warnings are errors in CI" >&2
    rm -f "$log"
    return 1
  fi
  rm -f "$log"
}

step "rustfmt"
cargo fmt --all -- --check

step "build e-puck2 firmware (release, thumbv7em-none-eabihf)"
build_no_warnings
cp "$tdir/thumbv7em-none-eabihf/release/firmware-rtic" "$tdir/firmware-epuck2.elf"

step "build QEMU firmware (release, --features qemu)"
build_no_warnings --features qemu
cp "$tdir/thumbv7em-none-eabihf/release/firmware-rtic" "$tdir/firmware-qemu.elf"

step "clippy (firmware both variants, host crates), warnings denied"
cargo clippy --release -j "$jobs" -- -D warnings
cargo clippy --release -j "$jobs" --features qemu -- -D warnings
cargo clippy -j "$jobs" --target "$host" -p drivers-logic -p host-tests --all-targets -- -D warnings

step "size report (budget: flash 128 KiB, static RAM 48 KiB)"
cargo run -q -j "$jobs" --target "$host" -p host-tests --bin size-report -- \
  "$tdir/firmware-epuck2.elf" "$tdir/firmware-qemu.elf"

step "host unit tests and QEMU end-to-end test"
log=$(mktemp)
REQUIRE_QEMU=1 FIRMWARE_QEMU_ELF="$(realpath "$tdir/firmware-qemu.elf")" \
  timeout "${FIRMWARE_CI_TIMEOUT:-300}" \
  cargo test -j "$jobs" --target "$host" -p drivers-logic -p host-tests 2>&1 | tee "$log"
passed=$(grep -o '[0-9]* passed' "$log" | awk '{s += $1} END {print s + 0}')
failed=$(grep -o '[0-9]* failed' "$log" | awk '{s += $1} END {print s + 0}')
rm -f "$log"

step "emulated exploration: conquest explore --qemu 2 (real firmware in QEMU, simulated bodies)"
elf="$(realpath "$tdir/firmware-qemu.elf")"
# The debug build: `cargo test --workspace` in .ci/run has built it already.
(cd .. && cargo build -q -j "$jobs" -p phone-sim --bin conquest)
explore_log=$(mktemp)
if (cd .. && timeout "${FIRMWARE_EXPLORE_TIMEOUT:-300}" \
  cargo run -q -j "$jobs" -p phone-sim --bin conquest -- \
  explore fields/small/open-6x6.field --qemu 2 --qemu-firmware "$elf" --json) | tee "$explore_log" \
  && grep -q '"complete":true' "$explore_log"; then
  passed=$((passed + 1))
else
  echo "firmware-rtic: the emulated exploration did not complete" >&2
  failed=$((failed + 1))
fi
rm -f "$explore_log"

step "done"
# Plain summary line for CI's test counter.
echo "firmware: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
