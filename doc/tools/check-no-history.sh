#!/bin/sh
# The user documentation and the public headers hold no history: no dates, issue numbers or
# unmet-target markers (the history is in CHANGELOG.md and git). ctest docs-no-history.
cd "$(dirname "$0")/../.." || exit 1
if grep -rnE '20[0-9]{2}-[0-9]{2}-[0-9]{2}|[Ii]ssue [0-9]+|NOT[ ]met' README.md doc/ modules/selfcalib/include; then
  echo "history found above: move it to CHANGELOG.md"
  exit 1
fi
echo "no dates, issue numbers or unmet-target markers in README.md, doc/ and modules/selfcalib/include"
