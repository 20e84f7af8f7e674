# bash completion for clothsim: its commands, each command's options (read off `clothsim
# COMMAND --help`, so they are the program's own), integrator names after --integrator(s),
# and scene files or the shipped scenes' bare names for a command's SCENE.
_clothsim() {
  local cur prev cmd words
  cur=${COMP_WORDS[COMP_CWORD]}
  prev=${COMP_WORDS[COMP_CWORD-1]}
  local commands="run compare bench converge stability validate encode imgdiff golden merge cache"
  if ((COMP_CWORD == 1)); then
    COMPREPLY=($(compgen -W "$commands --help --version" -- "$cur"))
    return
  fi
  cmd=${COMP_WORDS[1]}
  case $prev in
    --integrator | --integrators | --reference)
      local names
      names=$("${COMP_WORDS[0]}" run --help 2>/dev/null | sed -n 's/^ *--integrator TEXT *//p' | tr -d '|' | sed 's/(default.*//')
      COMPREPLY=($(compgen -W "$names course" -- "${cur##*,}"))
      return ;;
    -o | --output | --video | --frames | --csv | --plot | --summary | --metrics | --state | --export | --sheet | --junit)
      COMPREPLY=($(compgen -f -- "$cur"))
      return ;;
  esac
  if [[ $cur == -* ]]; then
    local options
    options=$("${COMP_WORDS[0]}" "$cmd" --help 2>/dev/null | grep -oE '^ +-[-a-zA-Z0-9,]+' | tr ',' '\n' | tr -d ' ')
    COMPREPLY=($(compgen -W "$options" -- "$cur"))
    return
  fi
  # A scene: YAML files and folders here, and the shipped scenes by name.
  local shipped
  shipped=$(ls "$(dirname "$(readlink -f "$(command -v "${COMP_WORDS[0]}")")")"/../share/clothsim/scenes 2>/dev/null | sed 's/\.yaml$//')
  COMPREPLY=($(compgen -f -X '!*.yaml' -- "$cur") $(compgen -d -- "$cur") $(compgen -W "$shipped" -- "$cur"))
}
complete -o filenames -F _clothsim clothsim
