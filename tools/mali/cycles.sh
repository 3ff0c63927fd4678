#!/usr/bin/env bash
# Mali-G52 (Bifrost) / Mali-G57 (Valhall) cycle counts for NAME.{vert,frag}.spv in DIR.
#   tools/mali/cycles.sh DIR [--gpus G52,G57] [--timeout S]   > cycles.json
# Builds the compiler first if needed (tools/mali/build.sh; $MALI_COMPILER skips that).
set -euo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if [ -z "${MALI_COMPILER:-}" ]; then
    MALI_COMPILER=$("$HERE/build.sh")
fi
exec python3 "$HERE/cycles.py" --compiler "$MALI_COMPILER" "$@"
