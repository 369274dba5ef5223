#!/usr/bin/env bash
# Planted references for CommentReferencesCatchBadOnes (tools/check_refs.py --root on this folder).
# These resolve: engine/planted.sh, README "Exit status", docs/page.md section "Sorted lists",
# docs/page.md#sorted-lists, planted.sh.
# These do not:
# engine/frame.cpp
# README "Threat model"
# docs/page.md section "Wide lights"
# docs/page.md#wide-lights
# vsm_record.cpp
echo "# not a comment: engine/nothing.cpp"
