#!/usr/bin/env bash
# Install headless Chromium and its driver for the report browser test
# (tests/report/test_report_browser.py). Idempotent and quiet: does nothing
# when both are already installed. Needs root (or sudo) and network access.
set -euo pipefail

have() { command -v "$1" >/dev/null 2>&1; }

if { have chromium || have chromium-browser; } && have chromedriver; then
    exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    if have sudo; then SUDO="sudo"; else
        echo "install-chromium.sh: need root or sudo to apt-get install chromium" >&2
        exit 1
    fi
fi

export DEBIAN_FRONTEND=noninteractive
log="$(mktemp)"
if ! { $SUDO apt-get update -qq && \
       $SUDO apt-get install -y -qq --no-install-recommends chromium chromium-driver; } >"$log" 2>&1; then
    cat "$log" >&2
    rm -f "$log"
    echo "install-chromium.sh: apt-get failed" >&2
    exit 1
fi
rm -f "$log"
if ! have chromium && ! have chromium-browser; then
    echo "install-chromium.sh: chromium did not install" >&2
    exit 1
fi
