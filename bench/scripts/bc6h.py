#!/usr/bin/env python3
"""BC6H quality, measured with code the project did not write: each BC6H KTX2 that probefilter wrote
is decoded by bcdec (PyPI imagecodecs) and compared, level by level, with the RGBA16F KTX2 of the
same levels; beside it, the same RGBA16F levels encoded by ISPC texcomp's BC6H at profile `basic`
(PyPI ispc-texcomp) and decoded by bcdec. Per level: the multi-exposure PSNR (Munkberg et al. 2006:
exposures -10 to +10 stops, gamma 2.2, 8 bits), the relative L1 over every texel and over the
texels along the face edges (where a seam would show).

Usage: bc6h.py [--min-margin DB] [--sampled RAW]... [--json FILE] BC6H.ktx2 RGBA16F.ktx2 [BC6H.ktx2 RGBA16F.ktx2 ...]
--min-margin: exit 1 when a level of 4x4 or more has an mPSNR below ISPC's plus DB (e.g. -1).
--sampled: once per pair, the BC6H file's texels as a Vulkan device sampled them (tests/bc6h_sample):
exit 1 unless every one is bcdec's decode of the same block.
"""
import argparse
import json
import struct
import sys

import imagecodecs
import ispc_texcomp
import numpy as np

VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_BC6H_UFLOAT_BLOCK = 97, 143


def ktx2_levels(path):
    """(vkFormat, face size, bytes) per level of an uncompressed KTX2 cube."""
    data = open(path, "rb").read()
    vk_format, _, width, _, _, _, faces, level_count, scheme = struct.unpack_from("<9I", data, 12)
    if faces != 6 or scheme != 0:
        sys.exit(f"{path}: not a cube without supercompression")
    levels = []
    for m in range(level_count):
        offset, length, _ = struct.unpack_from("<3Q", data, 80 + 24 * m)
        levels.append((vk_format, max(width >> m, 1), data[offset:offset + length]))
    return levels


def half_faces(data, size):
    return np.frombuffer(data, np.float16).reshape(6, size, size, 4)[..., :3].astype(np.float32)


def decode_bc6h(data, size):
    """Each face's 4x4 blocks, decoded by bcdec. bcdec refuses 128 bytes or less, so a face's blocks
    go in one row, padded with copies of the last."""
    across = (size + 3) // 4
    blocks = np.frombuffer(data, np.uint8).reshape(6, across * across, 16)
    faces = []
    for face in blocks:
        count = max(len(face), 9)
        raw = face.tobytes() + face[-1].tobytes() * (count - len(face))
        row = imagecodecs.bcn_decode(raw, 6, shape=(4, 4 * count, 3)).astype(np.float32)
        image = np.zeros((4 * across, 4 * across, 3), np.float32)
        for k in range(across * across):
            y, x = divmod(k, across)
            image[4 * y:4 * y + 4, 4 * x:4 * x + 4] = row[:, 4 * k:4 * k + 4]
        faces.append(image[:size, :size])
    return np.stack(faces)


def encode_ispc(faces, size):
    """ISPC texcomp's BC6H (profile basic) of each face, its edge texels repeated to whole blocks."""
    across = (size + 3) // 4
    out = b""
    for face in faces:
        padded = np.pad(face, ((0, 4 * across - size), (0, 4 * across - size), (0, 0)), mode="edge")
        rgba = np.ones((4 * across, 4 * across, 4), np.float16)
        rgba[..., :3] = padded.astype(np.float16)
        surface = ispc_texcomp.RGBASurface(rgba.tobytes(), 4 * across, 4 * across, 4 * across * 8)
        out += ispc_texcomp.compress_blocks_bc6h(surface, ispc_texcomp.BC6HEncSettings.from_profile("basic"))
    return out


def mpsnr(reference, test):
    errors = []
    for stops in range(-10, 11):
        def tone(x):
            return np.clip(255.0 * np.power(np.maximum(x, 0.0) * 2.0 ** stops, 1 / 2.2), 0, 255)
        errors.append(np.mean((tone(reference) - tone(test)) ** 2))
    mse = float(np.mean(errors))
    return 10 * np.log10(255.0 ** 2 / mse) if mse > 0 else float("inf")


def relative_l1(reference, test, mask=None):
    if mask is not None:
        reference, test = reference[:, mask], test[:, mask]
    return float(np.abs(test - reference).sum() / max(np.abs(reference).sum(), 1e-30))


def edge_mask(size):
    mask = np.zeros((size, size), bool)
    mask[0, :] = mask[-1, :] = mask[:, 0] = mask[:, -1] = True
    return mask


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--min-margin", type=float)
    parser.add_argument("--sampled", action="append", default=[])
    parser.add_argument("--json")
    parser.add_argument("files", nargs="+")
    args = parser.parse_args()
    if len(args.files) % 2:
        sys.exit("bc6h.py: expected pairs of BC6H.ktx2 RGBA16F.ktx2")
    if args.sampled and len(args.sampled) != len(args.files) // 2:
        sys.exit("bc6h.py: --sampled takes one file per pair")
    rows, failures = [], []
    print("| probe | level size | mPSNR dB | ISPC basic mPSNR dB | margin dB | relative L1 | ISPC | edge L1 | ISPC edge L1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for pair, (bc6h_path, half_path) in enumerate(zip(args.files[::2], args.files[1::2])):
        bc6h, half = ktx2_levels(bc6h_path), ktx2_levels(half_path)
        sampled = np.fromfile(args.sampled[pair], np.float32) if args.sampled else None
        first = 0
        if bc6h[0][0] != VK_FORMAT_BC6H_UFLOAT_BLOCK or half[0][0] != VK_FORMAT_R16G16B16A16_SFLOAT:
            sys.exit(f"bc6h.py: {bc6h_path} must be BC6H and {half_path} RGBA16F")
        if [level[1] for level in bc6h] != [level[1] for level in half]:
            sys.exit(f"bc6h.py: {bc6h_path} and {half_path} have different levels")
        for (_, size, blocks), (_, _, texels) in zip(bc6h, half):
            reference = half_faces(texels, size)
            ours, ispc = decode_bc6h(blocks, size), decode_bc6h(encode_ispc(reference, size), size)
            row = {"probe": bc6h_path, "size": size, "mpsnr": mpsnr(reference, ours), "ispc_mpsnr": mpsnr(reference, ispc),
                   "relative_l1": relative_l1(reference, ours), "ispc_relative_l1": relative_l1(reference, ispc),
                   "edge_l1": relative_l1(reference, ours, edge_mask(size)),
                   "ispc_edge_l1": relative_l1(reference, ispc, edge_mask(size))}
            row["margin"] = row["mpsnr"] - row["ispc_mpsnr"]
            rows.append(row)
            print(f"| {bc6h_path} | {size} | {row['mpsnr']:.2f} | {row['ispc_mpsnr']:.2f} | {row['margin']:+.2f} | "
                  f"{row['relative_l1']:.5f} | {row['ispc_relative_l1']:.5f} | {row['edge_l1']:.5f} | {row['ispc_edge_l1']:.5f} |")
            if sampled is not None:
                device = sampled[first:first + ours.size].reshape(ours.shape)
                first += ours.size
                differ = int((device.astype(np.float16) != ours.astype(np.float16)).sum())
                if differ:
                    failures.append(f"{bc6h_path} level {size}^2: {differ} texel channels sampled by the device differ from bcdec's")
            if not np.isfinite(ours).all():
                failures.append(f"{bc6h_path} level {size}^2: a texel decodes to a value that is not finite")
            if args.min_margin is not None and size >= 4 and row["margin"] < args.min_margin:
                failures.append(f"{bc6h_path} level {size}^2: mPSNR {row['mpsnr']:.2f} dB, ISPC basic {row['ispc_mpsnr']:.2f} dB")
    if args.json:
        json.dump(rows, open(args.json, "w"), indent=1)
    for failure in failures:
        print("FAIL:", failure, file=sys.stderr)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
