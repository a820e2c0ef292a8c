#!/usr/bin/env bash
# Regenerates the README's gallery and charts from data_samples/ with the built CLI.
# Usage: docs/make_gallery.sh [build/cli/brdfbake]
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build/cli/brdfbake}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
out=docs/images

for spec in phong_eye phong_diffuse blinn_phong copper colorgram gooch silhouette measured_lobes prefilter_sky; do
  "$cli" bake "data_samples/specs/$spec.json" --out-dir "$work" --quiet
done
preview() { "$cli" preview "$work/$1" -o "$out/gallery_$2.png" --size 320 "${@:3}" > /dev/null; }
preview phong_diffuse.exr phong --object teapot
preview blinn_exact.exr blinn --object teapot
preview copper_reflectance.exr copper --object teapot --exposure -1
preview colorgram.exr colorgram --object torus
preview gooch.png gooch --object teapot --from sphere
preview silhouette.exr silhouette --object torus
preview phong_diffuse.exr phong_per_vertex --per-vertex --segments 8
preview measured_lobes_reflectance.exr measured_lobes --object teapot --exposure -3
preview sky_phong100_paraboloid.exr sky_phong100 --object teapot --view 0.3,0.2,1

# Speed against accuracy, one picture per model family (a panel per map of the spec).
"$cli" chart data_samples/specs/phong_eye.json -o "$out/chart_phong.png" --resolutions 32,64,128,256,512 --samples 1,4,16 \
  --csv "$out/chart_phong.csv" > /dev/null
cat > "$work/ct.json" <<'JSON'
{"maps": [{"output": "ct.exr", "parameterization": "sphere", "view": "fixed",
  "material": {"model": "cook_torrance", "mode": "lighting", "roughness": 0.3, "fresnel": {"f0": [0.955, 0.638, 0.538]}},
  "lights": [{"direction": [1, 1, 1]}]}]}
JSON
"$cli" chart "$work/ct.json" -o "$out/chart_cook_torrance.png" --resolutions 32,64,128,256 --samples 1,4,16 \
  --parameterizations sphere,paraboloid,cube --csv "$out/chart_cook_torrance.csv" > /dev/null
# Prefiltering the sky (the first map of data_samples/specs/prefilter_sky.json, Phong 100): every
# parameterization x the default resolutions 16, 32, 64 x auto, sh, direct, importance.
cat > "$work/sky.json" <<JSON
{"maps": [{"output": "sky_phong100_paraboloid.exr", "parameterization": "paraboloid", "resolution": 128,
  "environment": {"file": "$PWD/data_samples/environments/sky_latlong.exr", "lobe": "phong:100", "max_error": 0.01}}]}
JSON
"$cli" chart "$work/sky.json" -o "$out/chart_prefilter_sky.png" --csv "$out/chart_prefilter_sky.csv" > /dev/null


# Per-vertex interpolation error, and Zimmons 1999's line experiment with one polygon and unit segments.
"$cli" interpolation -o "$out/interpolation.png" --csv "$out/interpolation.csv" \
  --line-chart "$out/interpolation_line_one_polygon.png" > /dev/null
"$cli" interpolation --line-chart "$out/interpolation_line_unit_segments.png" --segment 1 > /dev/null
# Matcaps (docs/matcap.md): four materials under the sample environments.
docs/make_matcaps.sh "$cli" > /dev/null
echo "gallery and charts written to $out"
