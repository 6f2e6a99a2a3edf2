# Sourced by the bench/ scripts: PGBA from the environment, else the newest build*/bin/pgba of
# the checkout `here` (set by the caller); exits 2 with one line when there is none.
if [[ -z "${PGBA:-}" ]]; then PGBA=$(ls -t "$here"/build*/bin/pgba 2>/dev/null | head -1 || true); fi
[[ -x "${PGBA:-}" ]] || { echo "error: pgba binary not found; build it or set PGBA=" >&2; exit 2; }
