#!/usr/bin/env python3
"""A tiny external denoiser for Glint (docs/external-denoiser.md): a box blur of the colour.

    external_box_denoiser.py COLOR.pfm OUTPUT.pfm [RADIUS]

Reads a 3-channel PFM ("PF", either byte order), averages every pixel with its neighbours
within RADIUS pixels (default 1, a 3x3 box, clipped at the border) and writes a little-endian
PFM of the same size. Pure Python (no numpy) so that it runs anywhere: slow beyond a few hundred
thousand pixels. Replace the blur with your own network or tool; keep the file contract.

Wire it into Glint (format pfm; allow the script itself, not the Python interpreter):
    chmod +x docs/examples/external_box_denoiser.py
    glint-denoise apply noisy.exr --filter external --param format=pfm \
        --param 'command=["/full/path/to/external_box_denoiser.py","{color}","{output}","2"]' \
        --out boxed.exr
"""
import struct
import sys
from array import array


def read_pfm(path):
    """Returns (width, height, rows top-down as flat float arrays of 3 * width)."""
    with open(path, "rb") as f:
        data = f.read()
    header = []
    pos = 0
    while len(header) < 4:  # magic, width, height, scale, each ended by whitespace
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        header.append(data[start:pos].decode("ascii"))
    pos += 1  # the single whitespace byte after the scale
    magic, width, height, scale = header[0], int(header[1]), int(header[2]), float(header[3])
    if magic != "PF":
        raise ValueError(f"{path}: not a 3-channel PFM ('{magic}')")
    pixels = array("f")
    pixels.frombytes(data[pos:pos + width * height * 12])
    if len(pixels) != width * height * 3:
        raise ValueError(f"{path}: truncated pixel data")
    if (scale < 0) != (sys.byteorder == "little"):
        pixels.byteswap()
    rows = [pixels[y * width * 3:(y + 1) * width * 3] for y in range(height)]
    rows.reverse()  # PFM stores the bottom row first
    return width, height, rows


def write_pfm(path, width, height, rows):
    with open(path, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode("ascii"))
        for row in reversed(rows):
            out = array("f", row)
            if sys.byteorder != "little":
                out.byteswap()
            f.write(out.tobytes())


def box_blur(width, height, rows, radius):
    out = []
    for y in range(height):
        y0, y1 = max(0, y - radius), min(height - 1, y + radius)
        row = array("f", bytes(12 * width))
        for x in range(width):
            x0, x1 = max(0, x - radius), min(width - 1, x + radius)
            n = (y1 - y0 + 1) * (x1 - x0 + 1)
            for c in range(3):
                total = 0.0
                for j in range(y0, y1 + 1):
                    src = rows[j]
                    for i in range(x0, x1 + 1):
                        total += src[3 * i + c]
                row[3 * x + c] = total / n
        out.append(row)
    return out


def main(argv):
    if len(argv) not in (3, 4):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 64
    radius = int(argv[3]) if len(argv) == 4 else 1
    if radius < 0:
        print("RADIUS must be >= 0", file=sys.stderr)
        return 64
    width, height, rows = read_pfm(argv[1])
    write_pfm(argv[2], width, height, box_blur(width, height, rows, radius))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv))
    except (OSError, ValueError) as e:
        print(f"external_box_denoiser: {e}", file=sys.stderr)
        sys.exit(1)
