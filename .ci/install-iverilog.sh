#!/bin/sh
# Install Icarus Verilog (Debian/Ubuntu package iverilog) for the co-simulation of the
# generated RTL against the model in hw/tests/rtl_cosim.rs. Idempotent and quiet. Exits
# non-zero when iverilog cannot be installed, so CI fails instead of passing the
# co-simulation vacuously (the test itself also fails without iverilog). To run without it
# on purpose, set BUMPSIM_SKIP_IVERILOG=1: this script then only warns, and the test skips.
#
# Usage: .ci/install-iverilog.sh   (as root, or with sudo available)

if command -v iverilog >/dev/null 2>&1 && command -v vvp >/dev/null 2>&1; then
    exit 0
fi

fail() {
    echo "error: install-iverilog: $1" >&2
    case "${BUMPSIM_SKIP_IVERILOG:-}" in
    "" | 0)
        echo "error: install-iverilog: iverilog is needed by hw/tests/rtl_cosim.rs; set BUMPSIM_SKIP_IVERILOG=1 to run without it" >&2
        exit 1
        ;;
    *)
        echo "warning: install-iverilog: BUMPSIM_SKIP_IVERILOG is set: continuing without iverilog" >&2
        exit 0
        ;;
    esac
}

if [ "$(id -u)" -eq 0 ]; then
    SUDO=""
elif command -v sudo >/dev/null 2>&1; then
    SUDO="sudo -n"
else
    fail "not root and no sudo; iverilog not installed"
fi

if ! command -v apt-get >/dev/null 2>&1; then
    fail "apt-get not found; iverilog not installed"
fi

export DEBIAN_FRONTEND=noninteractive
log=$(mktemp)
if $SUDO apt-get update -qq >"$log" 2>&1 &&
    $SUDO apt-get install -y -qq --no-install-recommends iverilog >>"$log" 2>&1 &&
    command -v iverilog >/dev/null 2>&1; then
    rm -f "$log"
    echo "install-iverilog: $(iverilog -V 2>/dev/null | head -n 1)"
else
    tail -n 20 "$log" >&2
    rm -f "$log"
    fail "apt-get could not install iverilog"
fi
exit 0
