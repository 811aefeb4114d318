#!/usr/bin/env bash
# Rebuilds the pictures of the shipped settings and docs/geology_settings.md: `cavesim reproduce geology`
# does it; this wrapper stays for old habits. usage: scripts/geology_pictures.sh [CAVESIM [OUTROOT]]
exec "${1:-build/cavesim}" reproduce geology --out "${2:-out/geology}"
