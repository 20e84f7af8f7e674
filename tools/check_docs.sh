#!/bin/sh
# Checks that every pointer to a file or section in the docs and the comments resolves, then
# reruns every command whose output README.md, docs/report.md and docs/integrators.md quote, and fails when a
# printed value differs from the quoted one beyond its tolerance (tools/check_docs.py says
# how a quoted number is marked). The default set fits in about 2 minutes on a 2-core machine;
#   tools/check_docs.sh --full            every check, then every picture of docs/images remade
#                                         and compared with the tree's (5 to 7 minutes)
#   tools/check_docs.sh --pictures        the pictures alone (2 to 4 minutes)
#   tools/check_docs.sh --full --update   rewrite the quoted values and pictures that differ, and say which
exec /usr/bin/python3 "$(dirname "$0")/check_docs.py" "$@"
