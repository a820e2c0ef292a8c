#!/usr/bin/env bash
# Bakes the matcap gallery of docs/matcap.md with the built CLI: four materials under the sample
# environments, 192 x 192 sRGB PNGs in docs/images/, and each map's --json report (its error estimate)
# in docs/images/matcap_errors.json.
# Usage: docs/make_matcaps.sh [build/cli/brdfbake]
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build/cli/brdfbake}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
out=docs/images
sky=data_samples/environments/sky_latlong.exr
cube=data_samples/environments/colored_cube_latlong.exr

cat > "$work/gold.json" <<'JSON'
{"model": "cook_torrance", "distribution": "ggx", "roughness": 0.3,
 "fresnel": {"schlick": [1.0, 0.78, 0.34]}, "shadowing": "smith_separable"}
JSON
cat > "$work/copper.json" <<'JSON'
{"model": "cook_torrance", "distribution": "ggx", "roughness": 0.15,
 "fresnel": {"schlick": [0.955, 0.638, 0.538]}, "shadowing": "smith_correlated"}
JSON
cat > "$work/phong.json" <<'JSON'
{"model": "phong", "diffuse": [0.5, 0.12, 0.1], "specular": [0.4, 0.4, 0.4], "exponent": 200}
JSON

matcap() {  # NAME MATERIAL ENVIRONMENT [flags...]
  local name=$1 material=$2 environment=$3
  shift 3
  "$cli" matcap "$material" "$environment" --resolution 192 --threads 2 --quiet --json "$@" \
    -o "$out/matcap_$name.png" > "$work/$name.json"
  python3 -c "import json,sys; e=json.load(open(sys.argv[1]))['under_environment']; \
print(json.dumps({'map': sys.argv[2], 'material': e['material'], 'detail': e['detail'], \
'error_estimate': e['error_estimate'], 'lookup_rms': e['lookup_rms'], 'highlight_rms': e['highlight_rms'], \
'error_metric': e['error_metric']}))" "$work/$name.json" "matcap_$name.png" >> "$work/errors.jsonl"
}
matcap gold_sky "$work/gold.json" "$sky"
matcap copper_cube "$work/copper.json" "$cube"
matcap fit_sky data_samples/fits/synthetic_two_lobes.json "$sky"
matcap phong_sky "$work/phong.json" "$sky"
python3 -c "import json,sys; print(json.dumps([json.loads(l) for l in open(sys.argv[1])], indent=2))" \
  "$work/errors.jsonl" > "$out/matcap_errors.json"
echo "matcaps written to $out"
