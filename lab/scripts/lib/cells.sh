# Shared set-up of the quality scripts that run over the scenes' cells (auto_quality.sh,
# expected_oracle.sh, auto_variants.sh): source it with the script's arguments. It moves to the
# project root and sets `build` (first argument, default build), `bin`, `scenes` (the remaining
# arguments up to a `--`, default cornell pool dof glossy), `rest` (an array of the arguments
# after `--`) and `work` (a temporary folder removed on exit).
cd "$(dirname "${BASH_SOURCE[0]}")/../../.."
build=${1:-build}
shift || true
scenes=""
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  scenes="$scenes${scenes:+ }$1"
  shift
done
[ $# -gt 0 ] && shift
rest=("$@")
scenes=${scenes:-cornell pool dof glossy}
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
