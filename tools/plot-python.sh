#!/bin/bash
# Prints the Python that draws hrad's figures: $HRAD_PYTHON when set, else the first of
# python3 and /usr/bin/python3 that imports matplotlib; prints nothing (exit 1) when
# none does. For the tools that draw a figure after their runs (scaling-check,
# mpi-scaling): `py=$(tools/plot-python.sh) || ...`.
if [ -n "${HRAD_PYTHON:-}" ]; then
  echo "$HRAD_PYTHON"
  exit 0
fi
for c in python3 /usr/bin/python3; do
  if "$c" -c "import matplotlib" 2>/dev/null; then
    echo "$c"
    exit 0
  fi
done
exit 1
