#!/usr/bin/env bash
# Checks the layout rules of README's "Layout" section on the checkout it sits in:
# - nothing loose in src/, and src/core, src/scene, src/study, src/view, src/export, src/clip exist;
# - every quoted include in src/, render/ and tools/ names a library folder or a file in the
#   same folder, and no library includes one above it;
# - no source file over 600 lines, no folder over 25 source files;
# - no function over 80 lines (Universal Ctags' end: field) beyond the kernels listed below.
# Prints every breach on one line and exits 1 if there is any.
set -euo pipefail
cd "$(dirname "$0")/.."
fail=0
say() { echo "layout: $*"; fail=1; }

for d in core scene study view export clip; do [[ -d src/$d ]] || say "src/$d is missing"; done
for f in src/*.h src/*.cpp; do [[ -e $f ]] && say "$f is loose in src/"; done

# Which libraries a folder may include (its own first).
allowed() {
  case $1 in
    src/core*) echo "core" ;;
    src/view*) echo "view core" ;;
    src/scene*) echo "scene view core" ;;
    src/study*) echo "study scene view core" ;;
    src/export*) echo "export view core render/output_file.h" ;;  # the atomic-output helper only
    src/clip*) echo "clip export video render study scene view core" ;;  # the commands' work, under cli and python
    render*) echo "render view/render_frame.h view/render_settings.h" ;;
    tools/video*) echo "video render view/render_frame.h" ;;
    tools/fuzz*) echo "fuzz scene core" ;;  # fuzz/: the shared target in tests/fuzz
    tools/python*) echo "python clip render export study scene view core" ;;  # the CLI's sibling, not its user
    tools/*) echo "cli clip video render export study scene view core" ;;
  esac
}
while IFS= read -r f; do
  dir=$(dirname "$f")
  ok=$(allowed "$dir")
  while IFS= read -r inc; do
    [[ -z $inc ]] && continue
    if [[ $inc != */* ]]; then
      [[ -e $dir/$inc ]] || say "$f includes \"$inc\", which is not in its folder: name its library"
      continue
    fi
    [[ $inc == hwy/* ]] && continue  # Highway's own headers, quoted as its docs do
    match=0
    for a in $ok; do [[ $inc == "$a" || $inc == "$a"/* ]] && match=1; done
    ((match)) || say "$f includes \"$inc\": $dir may include only: $ok"
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f")
done < <(find src render tools -name '*.h' -o -name '*.cpp' | sort)

# Floors inside core (src/core/floors.txt): no include runs up a floor.
declare -A floor_of_entry=()
floor_names=()
while read -r name entries; do
  [[ -z $name || $name == \#* ]] && continue
  floor_names+=("$name")
  for e in $entries; do floor_of_entry[$e]=${#floor_names[@]}; done
done < src/core/floors.txt
core_floor() {  # $1: a path relative to src/core; prints its floor number, or nothing
  local rel=$1 stem
  for e in "${!floor_of_entry[@]}"; do
    [[ $e == */ && $rel == "$e"* ]] && { echo "${floor_of_entry[$e]}"; return; }
  done
  stem=${rel%-inl.h}; stem=${stem%.h}; stem=${stem%.cpp}
  echo "${floor_of_entry[$stem]:-}"
}
while IFS= read -r f; do
  rel=${f#src/core/}
  own=$(core_floor "$rel")
  if [[ -z $own ]]; then say "$f is on no floor of src/core/floors.txt"; continue; fi
  while IFS= read -r inc; do
    [[ -z $inc ]] && continue
    if [[ $inc == core/* ]]; then target=${inc#core/}
    elif [[ $inc != */* ]]; then target=$(dirname "$rel")/$inc; target=${target#./}
    else continue; fi
    to=$(core_floor "$target")
    [[ -n $to ]] && ((to > own)) &&
      say "$f (floor ${floor_names[own-1]}) includes \"$inc\" (floor ${floor_names[to-1]}): an include runs up a floor"
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f")
done < <(find src/core -name '*.h' -o -name '*.cpp' | sort)

while read -r n f; do
  [[ $f == total ]] && continue
  ((n > 600)) && say "$f has $n lines (at most 600)"
done < <(find src render tools -name '*.h' -o -name '*.cpp' | xargs wc -l)
while read -r n d; do
  ((n > 25)) && say "$d holds $n source files (at most 25)"
done < <(find src render tools tests -name '*.h' -o -name '*.cpp' | xargs -n1 dirname | sort | uniq -c)

# The registry's promise (issue 33): a method is its row (core/integrators/integrator.cpp) and
# its folder, so at most 3 files outside core/integrators name a specific IntegratorKind::.
named=$(grep -rl "IntegratorKind::" src render tools --include='*.h' --include='*.cpp' | grep -v '^src/core/integrators/' | sort)
count=$(grep -c . <<<"$named")
((count > 3)) && say "$count files outside src/core/integrators name a specific IntegratorKind:: (at most 3): $(tr '\n' ' ' <<<"$named")"

# Kernels allowed past 80 lines, each saying why in its own comment: FamilyAssemble, the SIMD
# Newton-block assembly (core/implicit/assembly_kernels.cpp). Add more with the variable.
long_ok=" FamilyAssemble ${CLOTHSIM_LONG_FUNCTIONS_OK:-} "
if command -v ctags >/dev/null; then
  while IFS=$'\t' read -r name file rest; do
    line=$(grep -o 'line:[0-9]*' <<<"$rest" | cut -d: -f2)
    end=$(grep -o 'end:[0-9]*' <<<"$rest" | cut -d: -f2)
    [[ -z $line || -z $end ]] && continue
    len=$((end - line + 1))
    ((len > 80)) && [[ $long_ok != *" $name "* ]] && say "$file:$line: $name is $len lines (at most 80)"
  done < <(find src render tools -name '*.cpp' -o -name '*.h' | xargs ctags -x --_xformat='%N	%F	line:%n end:%e' --kinds-c++=f 2>/dev/null)
else
  echo "layout: ctags not found, function lengths not checked (apt install universal-ctags)" >&2
fi
exit $fail
