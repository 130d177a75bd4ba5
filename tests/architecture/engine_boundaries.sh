#!/usr/bin/env bash
# The layering of docs/ARCHITECTURE.md, checked on the sources:
# - the geometry engine (server/engine) includes only itself, server/base,
#   Eigen and the standard library: no I/O library, JSON or HTTP;
# - its folders are the pipeline's stages, each including only itself and
#   the stages before it;
# - it raises only the geometry codes of base/status.hpp, never the codes of
#   formats, requests or the service;
# - base/ includes nothing but itself and the standard library;
# - json/ (bounded JSON reading) includes nothing of the project but base/;
# - no caller picks a behaviour from an error's message text;
# - proto/ (the API's request types) includes from the engine and meshio
#   only their plain vocabulary (the surface description and each option
#   group's settings), which includes nothing else of theirs: never an
#   algorithm's header or option struct.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
fail=0
report() { echo "FAIL: $1"; printf '%s\n' "$2" | sed 's/^/  /'; fail=1; }

hits=$(grep -rnE '#include "' "$root/server/engine" | grep -vE '#include "(engine|base)/' || true)
[[ -z $hits ]] || report "the engine includes a project header outside engine/ and base/" "$hits"
# The engine's folders are its pipeline's stages, in order; a file includes
# only its own stage and the stages before it (never a later one), and every
# source file lives in a stage folder.
stages=(common surface distance flatten sheet placement subdivision deform animation)
hits=$(find "$root/server/engine" -maxdepth 1 -type f \( -name '*.cpp' -o -name '*.hpp' \) || true)
[[ -z $hits ]] || report "an engine source file outside the stage folders" "$hits"
for dir in "$root"/server/engine/*/; do
  name=$(basename "$dir")
  [[ " ${stages[*]} " == *" $name "* ]] || report "server/engine/$name is not a stage" "add it to stages in $0"
done
for ((i = 0; i < ${#stages[@]}; ++i)); do
  later=("${stages[@]:i+1}")
  ((${#later[@]})) || continue
  pattern="#include \"engine/($(IFS='|'; echo "${later[*]}"))/"
  hits=$(grep -rnE "$pattern" "$root/server/engine/${stages[i]}" || true)
  [[ -z $hits ]] || report "engine/${stages[i]}/ includes a later stage" "$hits"
done
hits=$(grep -rnE '#include <(httplib|nlohmann|draco|tiny_gltf|CLI|openssl|fstream|iostream)' \
         "$root/server/engine" || true)
[[ -z $hits ]] || report "the engine includes an I/O, JSON or HTTP library" "$hits"
hits=$(grep -rnE 'ErrorCode::k(UnsupportedFormat|Malformed|NotFound|NotAcceptable|Unavailable)\b' \
         "$root/server/engine" || true)
[[ -z $hits ]] || report "the engine raises a code that belongs outside it" "$hits"
hits=$(grep -rnE '#include "' "$root/server/base" | grep -vE '#include "base/' || true)
[[ -z $hits ]] || report "base/ includes a project header outside it" "$hits"
hits=$(grep -rnE '#include "' "$root/server/json" | grep -vE '#include "(json|base)/' || true)
[[ -z $hits ]] || report "json/ includes a project header outside json/ and base/" "$hits"
# text/ (the typesetter) builds on the engine's types and base/ only: no
# I/O, JSON or HTTP (font bytes come from the service).
hits=$(grep -rnE '#include "' "$root/server/text" | grep -vE '#include "(text|engine|base)/' || true)
[[ -z $hits ]] || report "text/ includes a project header outside text/, engine/ and base/" "$hits"
hits=$(grep -rnE '#include <(httplib|nlohmann|draco|tiny_gltf|CLI|openssl|fstream|iostream)' \
         "$root/server/text" || true)
[[ -z $hits ]] || report "text/ includes an I/O, JSON or HTTP library" "$hits"
# part/ (printable parts) builds on the engine and base/ only, the same way.
hits=$(grep -rnE '#include "' "$root/server/part" | grep -vE '#include "(part|engine|base)/' || true)
[[ -z $hits ]] || report "part/ includes a project header outside part/, engine/ and base/" "$hits"
hits=$(grep -rnE '#include <(httplib|nlohmann|draco|tiny_gltf|CLI|openssl|fstream|iostream)' \
         "$root/server/part" || true)
[[ -z $hits ]] || report "part/ includes an I/O, JSON or HTTP library" "$hits"
hits=$(grep -rnE '(message|error)\(\)\.(rfind|find|starts_with|compare)\(|field\(\) == "' \
         "$root/server" "$root/proto" "$root/client/cli" || true)
[[ -z $hits ]] || report "a caller decides from an error's text" "$hits"
hits=$(grep -rnE 'error\.rfind\("|message\.rfind\("' "$root/server" "$root/proto" "$root/client/cli" || true)
[[ -z $hits ]] || report "a caller decides from an error's text" "$hits"
vocabulary='(engine/(surface/(surface_spec|surface_fields|surface|sampling_options)|animation/animation_spec|flatten/flatten_settings|common/(placement_settings|geometry_types)|subdivision/(subdivision_settings|subdivision_mode)|sheet/sheet_mark)|meshio/draco_options|text/text_settings|part/part_settings)\.hpp'
hits=$(grep -rnE '#include "(engine|meshio|text|part)/' "$root/proto" | grep -vE "#include \"$vocabulary\"" || true)
[[ -z $hits ]] || report "proto includes an engine or meshio header that is not vocabulary" "$hits"
for header in $(grep -ohE "$vocabulary" -r "$root/proto" | sort -u); do
  hits=$(grep -nE '#include "(engine|meshio|text|part)/' "$root/server/$header" |
           grep -vE "#include \"$vocabulary\"" || true)
  [[ -z $hits ]] || report "the vocabulary header $header includes more than vocabulary" "$hits"
done
((fail == 0)) && echo "engine boundaries: all hold"
exit $fail
