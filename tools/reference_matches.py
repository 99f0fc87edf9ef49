#!/usr/bin/env python3
"""Exit 0 when DIR/reference.json was traced at WxH with SPP rays per pixel, 1 otherwise (missing or
different): lets tools/walks.sh and tools/bench_place.sh reuse a reference instead of tracing it again.
Usage: reference_matches.py DIR WxH SPP"""
import json
import sys

try:
    r = json.load(open(f"{sys.argv[1]}/reference.json"))
except (OSError, ValueError):
    sys.exit(1)
sys.exit(0 if f"{r['width']}x{r['height']}" == sys.argv[2] and r["spp"] == int(sys.argv[3]) else 1)
