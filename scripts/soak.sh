#!/usr/bin/env bash
# Soak test of the planning service (issue 17): starts build/bin/hfts-server
# with default limits on the databases in build/databases, drives it for
# MINUTES with 64 clients of mixed traffic, samples its memory, descriptors,
# threads and latencies, and fails when something grows, a request goes
# unanswered or the server dies (tests/cli/soak.py says exactly what is judged).
# Writes samples.csv, summary.json, soak.png and server.log to DIR
# (default build/soak/). Further options go to the driver (--clients N,
# --interval S, --host H --port P --pid PID for a running server; --help).
#
#   scripts/soak.sh MINUTES [--out DIR] [driver options]
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -lt 1 || "$1" == -* ]]; then
  echo "usage: scripts/soak.sh MINUTES [--out DIR] [driver options]" >&2
  [[ "${1:-}" == -h || "${1:-}" == --help ]] && exec /usr/bin/python3 tests/cli/soak.py --help
  exit 2
fi
if [[ ! -x build/bin/hfts-server ]]; then
  echo "soak: build/bin/hfts-server not found; run scripts/build.sh first" >&2
  exit 2
fi
exec /usr/bin/python3 tests/cli/soak.py "$@"
