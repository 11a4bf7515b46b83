#!/usr/bin/python3
"""Reads a `vsculpt play --out X.dxf` export of a sketch session back with ezdxf (a third-party
DXF library) and checks what CAD users get: the sculpture as 3DFACEs on layer "sculpture",
the sketch curves as 3D polylines on layer "sketch", every vertex finite, no audit errors, and
at least MIN_CLOSED of them closed polylines (the loops the sketch closed).
Usage: check_sketch_dxf.py FILE.dxf MIN_CURVES [MIN_CLOSED]"""
import math
import sys

import ezdxf

path, min_curves = sys.argv[1], int(sys.argv[2])
min_closed = int(sys.argv[3]) if len(sys.argv) > 3 else 0
doc = ezdxf.readfile(path)
auditor = doc.audit()
if auditor.has_errors:
    sys.exit(f"{path}: ezdxf audit found {len(auditor.errors)} error(s)")
faces = [e for e in doc.modelspace() if e.dxftype() == "3DFACE"]
curves = [e for e in doc.modelspace() if e.dxftype() == "POLYLINE"]
if not faces or any(f.dxf.layer != "sculpture" for f in faces):
    sys.exit(f"{path}: expected 3DFACEs on layer 'sculpture'")
if len(curves) < min_curves or any(c.dxf.layer != "sketch" for c in curves):
    sys.exit(f"{path}: expected at least {min_curves} POLYLINEs on layer 'sketch', got {len(curves)}")
for c in curves:
    points = [v.dxf.location for v in c.vertices]
    if len(points) < 2 or not all(math.isfinite(x) for p in points for x in p):
        sys.exit(f"{path}: a sketch polyline with fewer than 2 points or a non-finite vertex")
closed = sum(1 for c in curves if c.is_closed)
if closed < min_closed:
    sys.exit(f"{path}: expected at least {min_closed} closed sketch polylines, got {closed}")
print(f"{path}: {len(faces)} 3DFACEs, {len(curves)} sketch polylines ({closed} closed), audit clean")
