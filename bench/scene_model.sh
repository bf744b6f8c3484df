#!/usr/bin/env bash
# Issue 25's scene-model figures, measured in this run with build/wavemmlt:
#   1. a textured rough conductor (a bitmap on specular_reflectance and one on alpha)
#      against the same conductor with constants: CPU seconds (user + system), medians of
#      REPS interleaved runs, PT and BPT;
#   2. a grid mesh placed N times by instances against N flattened copies: --stats' meshes
#      and Embree bytes, the process's peak RSS (GNU time) and its build + render CPU time;
#   3. a ceiling panel whose radiance is a 64 x 64 bitmap (a bright spot on a dim screen:
#      a textured mesh light, sampled by its luminance) against the same panel with a
#      constant radiance of the same power: CPU seconds of PT and BPT (medians of REPS);
#   4. a principled floor (every reflecting lobe, constants) against a roughplastic one, and
#      the principled floor with bitmaps on base_color, roughness and metallic against its
#      constants: CPU seconds of PT and BPT (medians of REPS).
# Writes its scenes in a temporary folder; needs nothing from ../shared.
#
#   bench/scene_model.sh [--reps N] [--copies N]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=3 copies=256
while [ $# -gt 0 ]; do
  case $1 in
    --reps) reps=$2; shift 2 ;; --copies) copies=$2; shift 2 ;;
    *) echo "scene_model.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "scene_model.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
command -v bc >/dev/null || { echo "scene_model.sh: needs bc (apt-get install bc)" >&2; exit 1; }
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
python3 - "$tmp" "$copies" <<'PY'
import sys, struct, math
tmp, copies = sys.argv[1], int(sys.argv[2])
w = h = 64
with open(f"{tmp}/c.pfm", "wb") as f:  # a colour map and a roughness map
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
    for y in range(h):
        for x in range(w):
            f.write(struct.pack("<3f", 0.5 + 0.4 * math.sin(x / 5), 0.6, 0.4 + 0.3 * math.cos(y / 7)))
with open(f"{tmp}/a.pfm", "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
    for y in range(h):
        for x in range(w):
            a = 0.05 + 0.3 * ((x // 8 + y // 8) % 2)
            f.write(struct.pack("<3f", a, a, a))
head = """<scene version="3.0.0"><integrator type="path"><integer name="max_depth" value="6"/></integrator>
<sensor type="perspective"><float name="fov" value="50"/><transform name="to_world"><lookat origin="0, 2, 5" target="0, 0.5, 0" up="0, 1, 0"/></transform>
<film type="hdrfilm"><integer name="width" value="256"/><integer name="height" value="192"/><rfilter type="box"/></film></sensor>
<shape type="rectangle"><transform name="to_world"><scale value="8"/><rotate x="1" angle="-90"/></transform>%s</shape>
<shape type="sphere"><point name="center" x="0" y="3" z="1"/><float name="radius" value="0.4"/><emitter type="area"><rgb name="radiance" value="20"/></emitter></shape>
"""
const = '<bsdf type="roughconductor"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/><rgb name="specular_reflectance" value="0.7, 0.6, 0.5"/></bsdf>'
tex = ('<bsdf type="roughconductor"><string name="distribution" value="ggx"/>'
       '<texture type="bitmap" name="alpha"><string name="filename" value="a.pfm"/></texture>'
       '<texture type="bitmap" name="specular_reflectance"><string name="filename" value="c.pfm"/></texture></bsdf>')
open(f"{tmp}/const.xml", "w").write(head % const + "</scene>")
open(f"{tmp}/tex.xml", "w").write(head % tex + "</scene>")
n = 64  # a 2 x 64 x 64 triangle grid
with open(f"{tmp}/grid.obj", "w") as f:
    for j in range(n + 1):
        for i in range(n + 1):
            f.write(f"v {i / n} {0.05 * math.sin(i + 2 * j)} {j / n}\n")
    for j in range(n):
        for i in range(n):
            v = j * (n + 1) + i + 1
            f.write(f"f {v} {v + 1} {v + n + 2}\nf {v} {v + n + 2} {v + n + 1}\n")
side = int(math.ceil(math.sqrt(copies)))
place = lambda k: f'<transform name="to_world"><scale value="0.3"/><translate x="{(k % side - side / 2) * 0.35}" z="{(k // side - side / 2) * 0.35}"/></transform>'
diffuse = '<bsdf type="diffuse"/>'
inst = head % diffuse + '<shape type="shapegroup" id="g"><shape type="obj"><string name="filename" value="grid.obj"/></shape></shape>'
flat = head % diffuse
for k in range(copies):
    inst += f'<shape type="instance"><ref id="g"/>{place(k)}</shape>\n'
    flat += f'<shape type="obj"><string name="filename" value="grid.obj"/>{place(k)}</shape>\n'
open(f"{tmp}/inst.xml", "w").write(inst + "</scene>")
mean = 0.0
with open(f"{tmp}/panel.pfm", "wb") as f:  # a dim screen with a bright spot
    f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
    for y in range(h):
        for x in range(w):
            v = 0.2 + (200.0 if (x - 40) ** 2 + (y - 20) ** 2 < 25 else 0.0)
            mean += v / (w * h)
            f.write(struct.pack("<3f", v, v, v))
lit = lambda radiance: (head % diffuse).replace('<rgb name="radiance" value="20"/>', '<rgb name="radiance" value="0"/>') + (
    '<shape type="rectangle"><transform name="to_world"><scale value="1.2"/><rotate x="1" angle="90"/><translate y="3"/></transform>'
    f'<emitter type="area">{radiance}</emitter></shape></scene>')
open(f"{tmp}/panel_tex.xml", "w").write(lit('<texture type="bitmap" name="radiance"><string name="filename" value="panel.pfm"/></texture>'))
open(f"{tmp}/panel_const.xml", "w").write(lit(f'<rgb name="radiance" value="{mean}"/>'))
open(f"{tmp}/flat.xml", "w").write(flat + "</scene>")
lobes = ('<float name="anisotropic" value="0.3"/><float name="spec_tint" value="0.2"/><float name="sheen" value="0.4"/>'
         '<float name="clearcoat" value="0.5"/><float name="clearcoat_gloss" value="0.6"/>')
bitmap = lambda name, f: f'<texture type="bitmap" name="{name}"><string name="filename" value="{f}"/></texture>'
open(f"{tmp}/plastic.xml", "w").write(head % '<bsdf type="roughplastic"><float name="alpha" value="0.2"/><rgb name="diffuse_reflectance" value="0.6, 0.6, 0.5"/></bsdf>' + "</scene>")
open(f"{tmp}/principled.xml", "w").write(head % ('<bsdf type="principled"><rgb name="base_color" value="0.6, 0.6, 0.5"/><float name="roughness" value="0.4"/>'
                                               '<float name="metallic" value="0.3"/>' + lobes + '</bsdf>') + "</scene>")
open(f"{tmp}/principled_tex.xml", "w").write(head % ('<bsdf type="principled">' + bitmap("base_color", "c.pfm") + bitmap("roughness", "a.pfm") +
                                                   bitmap("metallic", "a.pfm") + lobes + '</bsdf>') + "</scene>")
PY
cpu() { /usr/bin/time -f "%U %S %M" -o "$tmp/t" build/wavemmlt "$@" --quiet --seed 1 -o "$tmp/o.pfm" --stats "$tmp/s.json"; awk '{printf "%.2f", $1 + $2}' "$tmp/t"; }
# PT and BPT on the scene $1 (the baseline, named $3, default constant) and $2 (named $4,
# default textured), interleaved REPS times.
versus() {
  local a=${3:-constant} b=${4:-textured}
  for t in pt bpt; do
    c=() x=()
    for ((r = 0; r < reps; ++r)); do
      c+=("$(cpu "$1" --tracer $t --spp 16)")
      x+=("$(cpu "$2" --tracer $t --spp 16)")
    done
    mc=$(median "${c[@]}") mx=$(median "${x[@]}")
    printf '%-4s %s %s  %s %s  medians %s / %s  %s/%s %.3f\n' "$t" "$a" "${c[*]}" "$b" "${x[*]}" "$mc" "$mx" "$b" "$a" "$(echo "$mx / $mc" | bc -l)"
  done
}
echo "== textured rough conductor (bitmaps on alpha and specular_reflectance) against constants, CPU s, medians of $reps"
versus "$tmp/const.xml" "$tmp/tex.xml"
echo "== $copies copies of a 8192-triangle grid: instances against flattened copies (PT, 4 spp)"
for s in inst flat; do
  secs=$(cpu "$tmp/$s.xml" --tracer pt --spp 4)
  rss=$(awk '{print $3}' "$tmp/t")
  meshes=$(grep -o '"meshes": [0-9]*' "$tmp/s.json" | awk '{print $2}')
  embree=$(grep -o '"embree": [0-9]*' "$tmp/s.json" | awk '{print $2}')
  printf '%-5s meshes %10d B  embree %10d B  peak RSS %7d KB  CPU %s s\n' "$s" "$meshes" "$embree" "$rss" "$secs"
done
echo "== a textured area light (64 x 64 bitmap) against a constant one of the same power, CPU s, medians of $reps"
versus "$tmp/panel_const.xml" "$tmp/panel_tex.xml"
echo "== a principled floor (every reflecting lobe) against a roughplastic one, CPU s, medians of $reps"
versus "$tmp/plastic.xml" "$tmp/principled.xml" roughplastic principled
# (their albedos differ, so do their paths: the CPU time per million rays, one PT run each)
for s in plastic principled; do
  secs=$(cpu "$tmp/$s.xml" --tracer pt --spp 16)
  rays=$(grep -o '"rays_[a-z]*": [0-9]*' "$tmp/s.json" | awk '{n += $2} END {print n}')
  printf '%-12s PT: %s CPU s, %d rays, %.3f CPU s per million rays\n' "$s" "$secs" "$rays" "$(echo "$secs * 1000000 / $rays" | bc -l)"
done
echo "== the principled floor with bitmaps on base_color, roughness and metallic against its constants, CPU s, medians of $reps"
versus "$tmp/principled.xml" "$tmp/principled_tex.xml"
