# Sourced by the comparisons that render with each of Glint's samplers (sampler_compare.sh,
# depth_compare.sh): the sampler is the scene's render.sampler (glint-render has no --sampler).
# with_sampler SCENE SAMPLER prints the path of a copy of SCENE beside it (so that its relative
# paths still resolve) with render.sampler set, named .sampler-PID-SAMPLER.json: the caller's exit
# trap removes them (remove_sampler_copies).
remove_sampler_copies() { rm -f scenes/*/.sampler-$$-*.json; }
with_sampler() {
  local copy="$(dirname "$1")/.sampler-$$-$2.json"
  python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s.setdefault("render", {})["sampler"]=sys.argv[2]; json.dump(s, open(sys.argv[3], "w"))' "$1" "$2" "$copy"
  echo "$copy"
}
