#!/usr/bin/env python3
"""Remakes the images of docs/gallery.md from the committed samples.

Each image is a before/after pair side by side (or stacked), made with the
release binary: `cargo build --release && python3 scripts/gallery.py`.
Needs Pillow (`pip install pillow`). Real facade photos are not shipped
(their licences allow research use only), so only the demo facade and the
CC0 brick sample appear here.
"""
import os
import subprocess
import sys
import tempfile

from PIL import Image

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("BIN", os.path.join(ROOT, "target", "release", "grime"))
OUT = os.path.join(ROOT, "docs", "gallery")


def grime(*args):
    subprocess.run([BIN, *args, "-q"], check=True)


def run(tmp, name, demo, *flags):
    path = os.path.join(tmp, name + ".png")
    grime("run", "--demo", demo, "-o", path, *flags)
    return Image.open(path).convert("RGB")


def pair(before, after, name, width=960, stacked=False):
    """Saves before|after (or before over after), scaled to `width`."""
    w, h = before.size
    if stacked:
        canvas = Image.new("RGB", (w, 2 * h + 8), "white")
        canvas.paste(before, (0, 0))
        canvas.paste(after, (0, h + 8))
    else:
        canvas = Image.new("RGB", (2 * w + 8, h), "white")
        canvas.paste(before, (0, 0))
        canvas.paste(after, (w + 8, 0))
    scale = width / canvas.size[0]
    canvas = canvas.resize((width, round(canvas.size[1] * scale)), Image.LANCZOS)
    canvas.save(os.path.join(OUT, name + ".jpg"), quality=85)


def crop(img, box, name, zoom=2):
    c = img.crop(box)
    c = c.resize((c.size[0] * zoom, c.size[1] * zoom), Image.NEAREST)
    c.save(os.path.join(OUT, name + ".jpg"), quality=90)


def small_png(img, name):
    """Saves a docs PNG under 200 KB: 256 colours, median cut."""
    img.quantize(256, method=Image.Quantize.MEDIANCUT).save(os.path.join(OUT, name), optimize=True)


def main():
    os.makedirs(OUT, exist_ok=True)
    none = ["--set", "rain.layers=0", "--set", "moss.enabled=false", "--set", "dust.enabled=false"]
    with tempfile.TemporaryDirectory() as tmp:
        for demo in ["facade", "brick"]:
            before = run(tmp, demo + "-before", demo, *none)
            after = run(tmp, demo + "-after", demo)
            pair(before, after, f"look-{demo}", stacked=(demo == "facade"))
            if demo == "facade":
                crop(after, (500, 330, 940, 720), "look-facade-detail")
                old = run(tmp, demo + "-30y", demo, "--years", "30")
                pair(after, old, "look-facade-30-years", stacked=True)
            for preset in ["rust-runs", "salt-bloom", "splash"]:
                if demo == "brick" and preset == "rust-runs":
                    continue  # a close-up has no ledges to hang fixings on
                styled = run(tmp, f"{demo}-{preset}", demo, "--preset", preset)
                pair(after, styled, f"gammaton-{preset}-{demo}", stacked=(demo == "facade"))
        for effect in ["scratches", "splotches", "stains", "mould", "rust", "smudges", "corrosion",
                       "spotty", "roughy", "fade", "desaturate"]:
            img = run(tmp, effect, "facade", *none, "--set", f"{effect}.enabled=true")
            small_png(img.crop((0, 360, 480, 720)), f"say-{effect}.png")
        sentence = "very rusty near the railings, slightly scratched, moderately mossy, stained below the sills"
        img = run(tmp, "sentence", "facade", "--say", sentence)
        small_png(img.resize((480, 360), Image.LANCZOS), "say-sentence.png")
    print("gallery images written to", OUT)


if __name__ == "__main__":
    sys.exit(main())
