#!/usr/bin/env bash
# What watching costs: the same render with and without --view (on an Xvfb of its own),
# and with --display-server to a listener that reads and drops everything, in pairs, for
# PT and MMLT. Prints per run the render's own seconds (--stats "seconds": scene building
# and the window's lifetime left out) and the process's CPU seconds (user + system: less
# sensitive than wall time to what else the machine runs, but it counts the window's whole
# life), then the medians per tracer. The goal: within 5%.
#   RUNS     pairs per tracer (default 3)
#   SIZE     image size WxH (default 320x240)
#   SPP      samples per pixel (default 64: a few seconds per render on 2 cores)
# Needs Xvfb, xdotool (scripts/setup.sh installs both), python3 and /usr/bin/time (package time).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/wavemmlt
runs=${RUNS:-3}
size=${SIZE:-320x240}
spp=${SPP:-64}
width=${size%x*}
height=${size#*x}
work=$(mktemp -d)
trap 'kill $xvfb_pid $sink_pid 2>/dev/null || true; rm -rf "$work"' EXIT

# An X server: Xvfb picks a free display and writes its number to fd 3.
exec 3> "$work/display"
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp -noreset 2>/dev/null &
xvfb_pid=$!
exec 3>&-
for _ in $(seq 100); do [ -s "$work/display" ] && break; sleep 0.1; done
export DISPLAY=":$(head -1 "$work/display")"

# A display server that reads everything and keeps nothing (tev's work left out).
python3 - "$work/port" <<'EOF' &
import socket, sys, threading
s = socket.socket(); s.bind(("127.0.0.1", 0)); s.listen(4)
open(sys.argv[1], "w").write(str(s.getsockname()[1]))
def drain(c):
    while c.recv(1 << 20): pass
while True:
    c, _ = s.accept(); threading.Thread(target=drain, args=(c,), daemon=True).start()
EOF
sink_pid=$!
for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
port=$(cat "$work/port")

seconds() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["seconds"])' "$1"; }

# render TRACER MODE: one render; prints its seconds and the process's CPU seconds.
render() {
  local tracer=$1 mode=$2 stats="$work/stats.json" cpu="$work/cpu.txt"
  rm -f "$stats"
  local args=(--tracer "$tracer" --width "$width" --height "$height" --spp "$spp" --quiet
              -o "$work/out.exr" --stats "$stats")
  case $mode in
    alone) nice -n 19 /usr/bin/time -o "$cpu" -f "%U %S" "$bin" "${args[@]}" ;;
    display) nice -n 19 /usr/bin/time -o "$cpu" -f "%U %S" "$bin" "${args[@]}" --display-server "127.0.0.1:$port" ;;
    view)
      nice -n 19 /usr/bin/time -o "$cpu" -f "%U %S" "$bin" "${args[@]}" --view &
      local pid=$!
      # The window stays open on the final image: close it once the render is done.
      local id
      id=$(timeout 600 xdotool search --sync --name "^wavemmlt $tracer: done" | head -1)
      xdotool windowfocus --sync "$id" key q 2>/dev/null || true
      wait "$pid" ;;
  esac
  echo "$(seconds "$stats"),$(awk '{print $1 + $2}' "$cpu")"
}

{
  echo "tracer,mode,run,seconds,cpu_seconds"
  for tracer in pt mmlt; do
    for r in $(seq "$runs"); do
      for mode in alone view display; do
        echo "$tracer,$mode,$r,$(render "$tracer" "$mode")"
      done
    done
  done
} | tee "$work/runs.csv"

python3 - "$work/runs.csv" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for tracer in sorted({r["tracer"] for r in rows}):
    for col, unit in (("seconds", "render s"), ("cpu_seconds", "CPU s")):
        t = {m: statistics.median(float(r[col]) for r in rows if r["tracer"] == tracer and r["mode"] == m)
             for m in ("alone", "view", "display")}
        for m in ("view", "display"):
            print(f"{tracer}: --{m if m == 'view' else 'display-server'}: median {t[m]:.3f} {unit} against "
                  f"{t['alone']:.3f} alone: {100 * (t[m] / t['alone'] - 1):+.1f}%")
EOF
