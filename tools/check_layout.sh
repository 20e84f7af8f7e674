#!/bin/sh
# The layout check (tools/check_layout.py says what it checks): the tree is the stack.
exec python3 "$(dirname "$0")/check_layout.py" "$@"
