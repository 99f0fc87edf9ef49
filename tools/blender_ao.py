"""Blender Cycles' AO pass of a camera path, for comparing `cubeao reference --aa N` with an offline
renderer (issue 17). Run by Blender (Debian package blender):

  blender -b --factory-startup -noaudio --python-exit-code 1 --python tools/blender_ao.py -- \
      MODEL.obj CAMERA.json OUTDIR --radius R [--frames A:B] [--width W --height H] [--samples S]

writes OUTDIR/ao_NNNN.exr (float, the AO in every channel; `cubeao compare OUTDIR REFERENCE_DIR`
reads its first). The OBJ is imported as it is (no axis change: the camera is given in the same
coordinates); the camera basis is cubeao's (core/camera.cpp): forward = normalize(target - eye),
right = normalize(forward x up), up' = right x forward, vertical field of view fov_y_deg. Cycles
traces one jittered camera ray and one cosine-weighted AO ray of length R per sample, box filter of
one pixel, no denoising, no adaptive sampling, fixed seed."""
import argparse
import json
import math
import os
import sys

import bpy
import mathutils


def parse():
    p = argparse.ArgumentParser(prog="blender_ao.py")
    p.add_argument("model")
    p.add_argument("camera")
    p.add_argument("out")
    p.add_argument("--radius", type=float, required=True)
    p.add_argument("--frames", default="")
    p.add_argument("--width", type=int, default=0)
    p.add_argument("--height", type=int, default=0)
    p.add_argument("--samples", type=int, default=256)
    return p.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])


def setup_scene(args, path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not args.model.lower().endswith(".obj"):
        sys.exit(f"blender_ao.py: {args.model}: only OBJ models (others: convert them first)")
    bpy.ops.wm.obj_import(filepath=args.model, forward_axis="Y", up_axis="Z")
    scene = bpy.context.scene
    cam = bpy.data.cameras.new("cam")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(path["fov_y_deg"])
    cam.clip_start, cam.clip_end = 1e-3, 1e5
    obj = bpy.data.objects.new("cam", cam)
    scene.collection.objects.link(obj)
    scene.camera = obj
    scene.world = bpy.data.worlds.new("world")
    scene.world.light_settings.distance = args.radius
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.use_adaptive_sampling, c.use_denoising = "CPU", args.samples, False, False
    c.pixel_filter_type, c.filter_width, c.seed = "BOX", 1.0, 1
    r = scene.render
    r.resolution_x = args.width or path["width"]
    r.resolution_y = args.height or path["height"]
    r.resolution_percentage = 100
    r.image_settings.file_format, r.image_settings.color_depth, r.image_settings.color_mode = "OPEN_EXR", "32", "RGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_layers[0].use_pass_ambient_occlusion = True
    scene.use_nodes = True
    tree = scene.node_tree
    tree.nodes.clear()
    layers = tree.nodes.new("CompositorNodeRLayers")
    tree.links.new(layers.outputs["AO"], tree.nodes.new("CompositorNodeComposite").inputs["Image"])
    return scene, obj


def camera_matrix(path, frame):
    eye, target = mathutils.Vector(frame["eye"]), mathutils.Vector(frame["target"])
    forward = (target - eye).normalized()
    right = forward.cross(mathutils.Vector(path.get("up", [0, 1, 0]))).normalized()
    up = right.cross(forward)
    m = mathutils.Matrix.Identity(4)
    for r in range(3):  # Blender's camera looks down its -Z with +Y up
        m[r][0], m[r][1], m[r][2], m[r][3] = right[r], up[r], -forward[r], eye[r]
    return m


def main():
    args = parse()
    path = json.load(open(args.camera))
    frames = path["frames"]
    a, b = 0, len(frames)
    if args.frames:
        lo, hi = args.frames.split(":")
        a, b = int(lo or 0), int(hi or len(frames))
    scene, cam = setup_scene(args, path)
    os.makedirs(args.out, exist_ok=True)
    for f in range(a, min(b, len(frames))):
        cam.matrix_world = camera_matrix(path, frames[f])
        scene.render.filepath = os.path.join(os.path.abspath(args.out), f"ao_{f:04d}.exr")
        bpy.ops.render.render(write_still=True)
        print(f"blender_ao.py: frame {f} -> {scene.render.filepath}", flush=True)


main()
