#!/usr/bin/env python3
"""Checks a PSD written by grime with psd-tools, an independent reader.

    python3 tests/psd_tools_check.py OUT.psd OUT.png LAYERS_DIR [--depth 8|16]

OUT.png is grime's flattened result (8-bit; tests/export_psd_tools.rs makes an
8-bit copy of a 16-bit result). LAYERS_DIR is what `--layers-dir` wrote for
the same run: its manifest.json says which layers, blend modes, opacities and
visibilities the PSD must have, and its PNGs what each layer holds.

Checks: depth and size; layer names bottom to top ("photo", the effect
layers, then the hidden "region" layer when there is a region); blend modes,
opacity bytes and visibility; every layer's pixels against its PNG; the
merged image section and psd-tools' own compositing of the layers against
OUT.png, within 2/255 per channel; the ICC profile (image resource 1039) is
there and is sRGB for these photos without one of their own, readable by
LittleCMS (Pillow's ImageCms). Exits 1 with a message on any mismatch.
"""

import argparse
import io
import json
import sys
from pathlib import Path

import numpy as np
from PIL import Image
from psd_tools import PSDImage
from psd_tools.constants import BlendMode, Resource

TOLERANCE = 2  # per channel, in 1/255

BLEND = {"normal": BlendMode.NORMAL, "multiply": BlendMode.MULTIPLY, "screen": BlendMode.SCREEN}

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)


def as_rgb255(img):
    return np.asarray(img.convert("RGB"), dtype=np.float64)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("psd")
    ap.add_argument("png")
    ap.add_argument("layers_dir")
    ap.add_argument("--depth", type=int, default=8)
    args = ap.parse_args()

    psd = PSDImage.open(args.psd)
    reference = as_rgb255(Image.open(args.png))
    layers_dir = Path(args.layers_dir)
    manifest = json.loads((layers_dir / "manifest.json").read_text())

    check(psd.depth == args.depth, f"depth {psd.depth}, want {args.depth}")
    icc = psd.image_resources.get_data(Resource.ICC_PROFILE)
    check(icc is not None, "no ICC profile (image resource 1039)")
    if icc is not None:
        from PIL import ImageCms

        try:
            desc = ImageCms.getProfileDescription(ImageCms.ImageCmsProfile(io.BytesIO(icc)))
            check("sRGB" in desc, f"ICC profile is {desc!r}, want sRGB")
        except Exception as e:  # noqa: BLE001 - any LittleCMS failure is a bad profile
            check(False, f"LittleCMS cannot read the ICC profile: {e}")
    check((psd.width, psd.height) == (manifest["width"], manifest["height"]), "canvas size")
    check(reference.shape[:2] == (psd.height, psd.width), "PNG size differs from the PSD")

    # Layers, bottom to top (psd-tools iterates bottom first).
    want = [dict(entry) for entry in manifest["layers"]]
    if manifest.get("region"):
        want.append(
            {"name": "region", "blend": "normal", "opacity": 1.0, "visible": False, "file": None}
        )
    got = list(psd)
    check(
        [layer.name for layer in got] == [w["name"] for w in want],
        f"layer names {[layer.name for layer in got]}, want {[w['name'] for w in want]}",
    )
    for layer, w in zip(got, want):
        name = w["name"]
        check(layer.kind == "pixel", f"{name}: kind {layer.kind}")
        check(layer.blend_mode == BLEND[w["blend"]], f"{name}: blend {layer.blend_mode}")
        check(layer.opacity == round(w["opacity"] * 255), f"{name}: opacity {layer.opacity}")
        check(layer.visible == w["visible"], f"{name}: visible {layer.visible}")
        check(layer.bbox == (0, 0, psd.width, psd.height), f"{name}: bbox {layer.bbox}")
        pixels = layer.numpy()  # float 0..1, RGBA
        if w["file"]:
            # PIL reads a 16-bit RGB PNG (the photo of a 16-bit run) as its
            # high bytes: allow 1/255 there; 8-bit layers must match exactly.
            tol = 1.0 if args.depth == 16 and name == "photo" else 0.01
            png = np.asarray(Image.open(layers_dir / w["file"]).convert("RGBA"), dtype=np.float64) / 255.0
            check(pixels.shape == png.shape, f"{name}: shape {pixels.shape}, want {png.shape}")
            if pixels.shape == png.shape:
                diff = np.abs(pixels - png).max() * 255
                check(diff <= tol, f"{name}: pixels differ by {diff:.2f}/255")
        else:
            region = np.asarray(Image.open(layers_dir / manifest["region"]).convert("L"), dtype=np.float64)
            diff = np.abs(pixels[..., 3] * 255 - region).max()
            check(diff <= 0.01, f"region: alpha differs by {diff:.2f}/255")
            check(np.all(pixels[..., :3] == 1.0), "region: not white")

    # The merged image section (what viewers that ignore layers show).
    preview = as_rgb255(psd.composite())
    d_preview = np.abs(preview - reference).max()
    # psd-tools compositing the layers itself, in float.
    from psd_tools.composite import composite

    color, _shape, _alpha = composite(psd, force=True)
    layers_rgb = np.clip(np.round(np.asarray(color)[..., :3] * 255), 0, 255)
    d_layers = np.abs(layers_rgb - reference).max()
    d_pil = np.abs(as_rgb255(psd.composite(force=True)) - reference).max()
    print(
        f"psd-tools: merged image max diff {d_preview:.0f}/255, "
        f"layers composited max diff {d_layers:.0f}/255 (mean {np.abs(layers_rgb - reference).mean():.3f}), "
        f"PIL composite(force=True) max diff {d_pil:.0f}/255"
    )
    check(d_preview <= TOLERANCE, f"merged image differs from the PNG by {d_preview}/255")
    check(d_layers <= TOLERANCE, f"psd-tools' composite of the layers differs by {d_layers}/255")
    check(d_pil <= TOLERANCE, f"psd-tools' PIL composite differs by {d_pil}/255")

    if failures:
        for f in failures:
            print("FAIL:", f, file=sys.stderr)
        return 1
    print(f"psd-tools: {len(got)} layers OK")
    return 0


if __name__ == "__main__":
    sys.exit(main())
