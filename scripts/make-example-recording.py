#!/usr/bin/env python3
"""Writes examples/tracker-session.vsrec: a device recording built from the documented report
layouts (devices_report.md section 1.3 Liberty binary records, section 2.2 3Dconnexion
reports), so `vsculpt play` can show the device path without hardware. A Liberty HS tracker
pen draws a ring on the sphere, the 3D mouse steps the size down, turns the sculpture a
little and switches to carve, and the pen carves a groove across the top."""
import json
import math
import struct
import sys

MS = 1_000_000
events = []


def ev(t, dev, kind, data=b""):
    events.append(f"{t} {dev} {kind}" + (" " + data.hex() if data else ""))


def liberty(station, x_mm, y_mm, z_mm, frame):
    # Position in cm, unit quaternion, timestamp ms, frame count, trailing space.
    body = struct.pack("<3f4fII", x_mm / 10, y_mm / 10, z_mm / 10, 1, 0, 0, 0, frame * 4, frame)
    return b"LY" + bytes([station, ord("C"), ord(" "), 0, 37, 0]) + body + b" "


def axes(report_id, a, b, c):
    return struct.pack("<Bhhh", report_id, a, b, c)


def buttons(bits):
    return bytes([3, bits, 0])


t = 0
ev(t, "tracker", "arrived", struct.pack("<HH", 0x0F44, 0xFF20))
ev(t, "mouse", "arrived", struct.pack("<HH", 0x256F, 0xC635))
# Left button twice: size 7 -> 6 -> 5.
for _ in range(2):
    t += 50 * MS
    ev(t, "mouse", "report", buttons(1))
    t += 50 * MS
    ev(t, "mouse", "report", buttons(0))
frame = 0
# Stroke 1 (add): a ring of radius 25 mm at height 36 mm.
for i in range(121):
    a = 2 * math.pi * i / 120
    t += 8 * MS
    ev(t, "tracker", "report", liberty(1, 25 * math.cos(a), 25 * math.sin(a), 36, frame))
    frame += 1
# Right button: carve (ends the stroke). The 3D mouse turns the sculpture 0.3 s at half speed.
t += 50 * MS
ev(t, "mouse", "report", buttons(2))
t += 50 * MS
ev(t, "mouse", "report", buttons(0))
for i in range(31):
    t += 10 * MS
    ev(t, "mouse", "report", axes(2, 175 if i < 30 else 0, 0, 0))
# Stroke 2 (carve): a groove across the top.
for i in range(81):
    t += 8 * MS
    ev(t, "tracker", "report", liberty(1, -40 + i, 0, 39, frame))
    frame += 1
t += 50 * MS
ev(t, "tracker", "left")
ev(t, "mouse", "left")

# A recorded config without initial_sphere.core_weight reads as one made before the steep core
# (docs/projects.md), so the keys are given: the example plays with today's sphere.
config = {"polygonizer": {"grid_n": 64},
          "initial_sphere": {"core_weight": 0.7, "core_support_over_radius": 1.3}, "devices": {"match": [
    {"name": "tracker", "driver": "polhemus", "access": "libusb", "vendor": 0x0F44, "products": [0xFF20]},
    {"name": "mouse", "driver": "spacemouse", "access": "hidraw", "vendor": 0x256F, "products": [0xC635]}]}}
out = sys.argv[1] if len(sys.argv) > 1 else "examples/tracker-session.vsrec"
with open(out, "w") as f:
    f.write("vsculpt-recording 1\n")
    f.write("# Made by scripts/make-example-recording.py from the documented report layouts.\n")
    f.write("meta config " + json.dumps(config) + "\n")
    f.write("device tracker polhemus libusb 0f44 ff20\n")
    f.write("device mouse spacemouse hidraw 256f c635\n")
    f.write("\n".join(events) + "\n")
