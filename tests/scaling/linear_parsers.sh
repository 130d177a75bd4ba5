#!/usr/bin/env bash
# Every parser of untrusted bytes is linear in time in each structural axis
# of its input (docs/RELIABILITY.md, item 31): for each shape of
# scaling_probe (request JSON: arrays of objects, long keys, numbers, keys,
# strings, nesting, a grid surface's points; meshes: OBJ faces, usemtl names
# and groups, PLY, STL, OFF, glTF nodes, node chains, meshes, accessors,
# primitives and extras), the input is doubled four times and the parse's
# instructions (valgrind's callgrind: the count does not move with the
# machine's load) must grow at most 2.2x per doubling. Request JSON's heap
# at its peak must stay within 40 bytes per input byte, and a glTF's extras
# (skipped as they are read) within 2.
#
# Usage: linear_parsers.sh SCALING_PROBE [SHAPE...]
set -euo pipefail
probe=$1
shift
command -v valgrind > /dev/null || { echo "linear_parsers: needs valgrind (scripts/setup.sh)" >&2; exit 1; }
shapes=("$@")
((${#shapes[@]})) || mapfile -t shapes < <("$probe" --list)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The smallest size of each shape (the largest is 16 times it): large enough
# that the parse outweighs its fixed cost, small enough for valgrind.
base_of() {
  case $1 in
    json_key_length) echo 4096 ;;
    obj_groups | gltf_primitives | gltf_meshes | gltf_accessors) echo 200 ;;
    *) echo 4000 ;;
  esac
}

fail=0
for shape in "${shapes[@]}"; do
  n=$(base_of "$shape")
  previous=0
  line="$shape:"
  for step in 0 1 2 3 4; do
    out=$work/cg.out
    report=$(valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$out" \
               "$probe" "$shape" "$n" 2> /dev/null)
    ir=$(awk '/^summary:/ {print $2}' "$out")
    read -r _ _ _ bytes _ code _ peak <<< "$report"
    line+=" n=$n ${ir}Ir"
    if ((previous > 0)); then
      ratio=$(python3 -c "print(f'{$ir / $previous:.2f}')")
      line+=" (x$ratio)"
      if python3 -c "import sys; sys.exit(0 if $ir <= 2.2 * $previous else 1)"; then :; else
        echo "FAIL: $shape: doubling to n=$n took ${ratio}x the instructions (limit 2.2x)"
        fail=1
      fi
    fi
    case $shape in
      json_*) per_byte_limit=40 ;;
      gltf_extras) per_byte_limit=2 ;;
      *) per_byte_limit=0 ;;
    esac
    if ((per_byte_limit > 0 && peak > per_byte_limit * bytes + 65536)); then
      echo "FAIL: $shape at n=$n ($bytes bytes): the parse's heap peaked at $peak bytes (limit $per_byte_limit per byte)"
      fail=1
    fi
    previous=$ir
    n=$((n * 2))
  done
  echo "$line (last: $bytes bytes, $code, heap peak $peak)"
done
((fail == 0)) && echo "linear parsers: every shape within 2.2x per doubling"
exit $fail
