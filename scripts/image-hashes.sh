#!/usr/bin/env bash
# Prints the SHA-256 of every tracer's image of a few scenes rendered with a fixed seed:
# a refactor must change no image, so run it with the binary before and after and compare.
#
#   scripts/image-hashes.sh [BINARY] > hashes.txt      # default BINARY: build/wavemmlt
#   diff <(scripts/image-hashes.sh old/wavemmlt) <(scripts/image-hashes.sh build/wavemmlt)
#
# Scenes: the built-in scene; the Cornell box and the seed room of tests/data; the seed
# appendix (an environment map, textures); and a small outdoor scene written here with a
# thin lens, a bump map, a glossy floor, glass and a mirror under the same environment map;
# two scenes of participating media (below), in RGB and spectral (pbrt files' default). Each with PT, LT, BPT, MMLT and PSSMLT (16 samples or mutations per pixel, 1024 chains, seed 7,
# 2 threads).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/wavemmlt}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
data=tests/data/scenes
cp "$data/seed-room/sky-4x2.pfm" "$tmp/"
cat > "$tmp/outdoor.xml" <<'EOF'
<Scene>
  <Settings><Width value="48"/><Height value="32"/><MaxPathLength value="8"/><EnvMap name="sky-4x2.pfm"/></Settings>
  <Camera Type="Camera"><Position x="0" y="1" z="-3.5"/><LookAt x="0" y="0.4" z="0"/><FOV value="40"/>
    <DOF value="1"/><F-Length value="3.5"/><F-Stop value="4"/></Camera>
  <Texture Type="Checker" ID="1"><Colour1 r="0" g="0" b="0"/><Colour2 r="1" g="1" b="1"/><Repeat u="6" v="6"/></Texture>
  <Shader Type="Glossy" ID="0"><Diffuse r="0.5" g="0.45" b="0.4"/><Specular r="0.3" g="0.3" b="0.3"/>
    <Shininess value="40"/><Bump value="1"/></Shader>
  <Shader Type="Dielectric" ID="1"><Reflect r="1" g="1" b="1"/><Refract r="1" g="1" b="1"/><iIOR value="1.5"/><oIOR value="1"/></Shader>
  <Shader Type="Reflective" ID="2"><Reflect r="0.9" g="0.9" b="0.9"/></Shader>
  <Geometry Type="Plane" ID="floor"><Position x="0" y="0" z="0"/><Width value="6"/><Depth value="6"/><Shader value="0"/></Geometry>
  <Geometry Type="Sphere" ID="glass"><Position x="0.6" y="0.35" z="-0.5"/><Radius value="0.35"/><Shader value="1"/></Geometry>
  <Geometry Type="Sphere" ID="mirror"><Position x="-0.5" y="0.45" z="0"/><Radius value="0.45"/><Shader value="2"/></Geometry>
  <Light Type="Area" ID="lamp"><Position x="0" y="2" z="0"/><Radius value="0.2"/><Intensity value="10"/></Light>
</Scene>
EOF
# Media (docs/media.md): fog around everything, a rough glass ball of a scattering medium, a
# grid of smoke behind an interface sphere; and the same with emitting media (PT, BPT, MMLT:
# the light tracer refuses them).
media() {  # media EXTRA-PARAMETERS-OF-THE-SMOKE
  cat <<MEDIA
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [ 0.02 0.02 0.02 ] "rgb sigma_s" [ 0.1 0.1 0.1 ] "float g" 0.5
MakeNamedMedium "milk" "string type" "homogeneous" "rgb sigma_a" [ 0.05 0.1 0.2 ] "rgb sigma_s" [ 2 1.5 1 ] "float g" 0.3
MakeNamedMedium "smoke" "string type" "uniformgrid" "rgb sigma_a" [ 0.5 0.5 0.5 ] "rgb sigma_s" [ 3 3 3 ] "float g" -0.2
  "integer nx" 2 "integer ny" 2 "integer nz" 2 "point3 p0" [ -1 0 -1 ] "point3 p1" [ 0 1 0 ] "float density" [ 0.2 1 0.5 1.5 0.8 0.1 1.2 0.6 ] $1
LookAt 0 1 -4  0 0.6 0  0 1 0
MediumInterface "" "fog"
Camera "perspective" "float fov" [ 35 ]
Film "rgb" "integer xresolution" [ 48 ] "integer yresolution" [ 32 ]
WorldBegin
MediumInterface "fog" "fog"
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
Shape "trianglemesh" "point3 P" [ -1 3 -1  1 3 -1  1 3 1  -1 3 1 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh" "point3 P" [ -5 0 -5  5 0 -5  5 0 5  -5 0 5 ] "integer indices" [ 0 2 1 0 3 2 ]
AttributeBegin
Material "dielectric" "float eta" 1.5 "float roughness" 0.3
MediumInterface "milk" "fog"
Translate 0.6 0.5 0
Shape "sphere" "float radius" 0.5
AttributeEnd
AttributeBegin
Material "interface"
MediumInterface "smoke" "fog"
Translate -0.5 0.5 -0.5
Shape "sphere" "float radius" 0.45
AttributeEnd
MEDIA
}
media "" > "$tmp/media.pbrt"
media '"rgb Le" [ 2 1 0.5 ]' > "$tmp/glow.pbrt"
scenes=("builtin|"
        "cornell|$data/bitterli-cornell/bitterli-cornell-256.xml --width 48 --height 48 --max-length 6"
        "seed-room|$data/seed-room/seed-room.xml --width 48 --height 48 --max-length 6"
        "seed-appendix|$data/seed-room/seed-appendix.xml --width 48 --height 32 --max-length 6"
        "outdoor|$tmp/outdoor.xml"
        "media|$tmp/media.pbrt --max-length 8 --rgb"
        "glow|$tmp/glow.pbrt --max-length 8 --rgb|pt bpt mmlt pssmlt"
        "media-spectral|$tmp/media.pbrt --max-length 8 --spectral"
        "glow-spectral|$tmp/glow.pbrt --max-length 8 --spectral|pt bpt mmlt pssmlt")
for entry in "${scenes[@]}"; do
  name=${entry%%|*} rest=${entry#*|}
  args=${rest%%|*} tracers="pt lt bpt mmlt pssmlt"
  [ "$rest" != "$args" ] && tracers=${rest#*|}
  [ "$name" = builtin ] && args="--width 48 --height 32"
  for tracer in $tracers; do
    # shellcheck disable=SC2086
    if "$bin" $args --tracer "$tracer" --spp 16 --chains 1024 --seed 7 --threads 2 --quiet -o "$tmp/out.pfm" 2>/dev/null; then
      echo "$name $tracer $(sha256sum "$tmp/out.pfm" | cut -c1-16)"
    else  # (a binary from before the tracer)
      echo "$name $tracer refused"
    fi
  done
done
