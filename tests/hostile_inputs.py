#!/usr/bin/env python3
"""Hostile inputs to probefilter, probebench and probefit: every one is refused with exit code 2 and one line on
stderr naming the file (or option) and the problem, within a few seconds and 1 GiB of resident
memory (the child's own getrusage), and nothing on disk is created or changed.

Outputs that are not the tool's to replace are among them: symbolic links (dangling, looping, to a
folder or a file), FIFOs, device nodes, a mount inside an output folder, links planted at the staging
names. Device nodes and mounts are made here, privately (a node in the work folder, a tmpfs in a mount
namespace of the suite's own); where that is not permitted those cases are skipped, and say so.

The hostile files are made here. Usage: hostile_inputs.py PROBEFILTER PROBEFIT PROBEBENCH
"""
import json
import os
import shutil
import re
import resource
import stat
import struct
import subprocess
import sys
import tempfile
import time
import zlib

PROBEFILTER, PROBEFIT, PROBEBENCH = (os.path.abspath(tool) for tool in sys.argv[1:4])
MAX_SECONDS = 10.0
MAX_RSS_MIB = 1024
work = tempfile.mkdtemp(prefix="hostile-")
tried = refused = 0


def path(name):
    return os.path.join(work, name)


def write(name, data):
    with open(path(name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())
    return path(name)


def snapshot():
    state = {}
    for root, dirs, files in os.walk(work):
        for name in dirs + files:
            full = os.path.join(root, name)
            st = os.lstat(full)
            state[full] = (st.st_mode, st.st_size, st.st_mtime_ns)
    return state


def limit_memory():
    # A safety net for the machine; the measure is the resident peak below.
    resource.setrlimit(resource.RLIMIT_AS, (8 << 30, 8 << 30))


def wait_with_usage(child, timeout):
    """Waits with wait4, so that the usage is the child's alone (Popen.wait would reap it first)."""
    deadline = time.monotonic() + timeout
    while True:
        pid, status, usage = os.wait4(child.pid, os.WNOHANG)
        if pid == child.pid:
            child.returncode = os.waitstatus_to_exitcode(status)
            return usage
        if time.monotonic() > deadline:
            child.kill()
            pid, status, usage = os.wait4(child.pid, 0)
            child.returncode = os.waitstatus_to_exitcode(status)
            return None
        time.sleep(0.01)


def expect_refused(name, needles, tool, *args):
    """Runs tool with args in the work folder; needles: texts the one-line message must hold."""
    global tried, refused
    tried += 1
    before = snapshot()
    start = time.monotonic()
    err_path = os.path.join(tempfile.gettempdir(), f"hostile-stderr-{os.getpid()}")
    with open(err_path, "wb") as err:
        child = subprocess.Popen([tool, *args], stdout=subprocess.DEVNULL, stderr=err, cwd=work, preexec_fn=limit_memory)
        usage = wait_with_usage(child, 60)
    seconds = time.monotonic() - start
    with open(err_path, "rb") as err:
        text = err.read().decode(errors="replace")
    os.remove(err_path)
    problems = []
    if usage is None: problems.append("still running after 60 s")
    rss_mib = usage.ru_maxrss / 1024 if usage else 0
    lines = text.splitlines()
    if child.returncode != 2: problems.append(f"exit code {child.returncode}, expected 2")
    if len(lines) != 1: problems.append(f"{len(lines)} lines on stderr, expected 1")
    for needle in needles:
        if needle not in text: problems.append(f"message lacks '{needle}'")
    if seconds > MAX_SECONDS: problems.append(f"took {seconds:.1f} s (limit {MAX_SECONDS:.0f})")
    if rss_mib > MAX_RSS_MIB: problems.append(f"peak resident memory {rss_mib:.0f} MiB (limit {MAX_RSS_MIB})")
    if snapshot() != before: problems.append("files created or changed on disk")
    if problems:
        print(f"FAIL {name}: {'; '.join(problems)}: {text.strip()[:300]}")
    else:
        refused += 1
        print(f"ok {name} ({seconds:.2f} s, {rss_mib:.0f} MiB): {text.strip()}")


def fnv1a(data):
    """The hash in an output folder's staging name (core's staged_output.cpp)."""
    h = 2166136261
    for byte in data:
        h = ((h ^ byte) * 16777619) & 0xFFFFFFFF
    return h


def expect_written(name, args, outputs, precious):
    """Runs a command that must succeed beside links planted in its output's folder: exit 0, `outputs`
    written, every link in that folder still there with its target, and `precious` unchanged."""
    global tried, refused
    tried += 1
    folder = os.path.dirname(precious)
    links = {n: os.readlink(os.path.join(folder, n)) for n in os.listdir(folder) if os.path.islink(os.path.join(folder, n))}
    with open(precious, "rb") as f:
        before = f.read()
    result = subprocess.run(args, cwd=work, capture_output=True, text=True)
    problems = []
    if result.returncode != 0: problems.append(f"exit code {result.returncode}: {result.stderr.strip()[:200]}")
    problems += [f"{out} not written" for out in outputs if not os.path.exists(out)]
    for n, target in links.items():
        link = os.path.join(folder, n)
        if not os.path.islink(link) or os.readlink(link) != target: problems.append(f"link {n} changed")
    with open(precious, "rb") as f:
        if f.read() != before: problems.append(f"{precious} written through a link")
    if problems:
        print(f"FAIL {name}: {'; '.join(problems)}")
    else:
        refused += 1
        print(f"ok {name}: written beside {len(links)} planted links, none followed")


# --- File makers ---------------------------------------------------------------------------------

def hdr(width_height_line, body=b"", header=b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n"):
    return header + width_height_line + b"\n" + body


def rle_scanline(width, runs):
    """A new-style run-length scanline: marker, then `runs` (raw count bytes and values) as given."""
    return bytes([2, 2, width >> 8, width & 255]) + runs


def exr_header(width, height, tiles=None, extra=b"", tiled_flag=None, display=None, channel_names=(b"B", b"G", b"R")):
    def attribute(name, kind, value):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value

    channels = b"".join(c + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in channel_names) + b"\0"
    window = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    version = 2 | (0x200 if (tiles if tiled_flag is None else tiled_flag) else 0)
    out = struct.pack("<ii", 20000630, version)
    out += attribute("channels", "chlist", channels)
    out += attribute("compression", "compression", b"\0")
    out += attribute("dataWindow", "box2i", window)
    out += attribute("displayWindow", "box2i", struct.pack("<iiii", *display) if display else window)
    out += attribute("lineOrder", "lineOrder", b"\0")
    out += attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    out += attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    out += attribute("screenWindowWidth", "float", struct.pack("<f", 1.0))
    if tiles: out += attribute("tiles", "tiledesc", struct.pack("<IIB", tiles[0], tiles[1], 0))
    return out + extra + b"\0"


def ktx2(vk_format, width, height, faces, level, scheme=0, texel_bytes=8, layers=0, offset=None, stored=None, kvd=(0, 0),
         tail=b""):
    """A KTX2 file of one level: the header (its key/value block's offset and length as given), level
    0's index entry (its offset and stored length as given, or those of `level`), the level's bytes,
    then `tail`."""
    count = width * height * faces * texel_bytes
    identifier = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
    header = identifier + struct.pack("<9I4I2Q", vk_format, 2, width, height, 0, layers, faces, 1, scheme, 0, 0, *kvd, 0, 0)
    index = struct.pack("<3Q", offset if offset is not None else 104, stored if stored is not None else len(level), count)
    return header + index + level + tail


def good_table_text():
    with open(path("gltf16_quad8.json")) as f:
        return f.read()


# --- The cases -----------------------------------------------------------------------------------

def main():
    tables = os.environ["PROBE_TABLES"]
    subprocess.run([PROBEFILTER, "synth", "sky", "--size", "16", "--out", path("good.exr")], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(tables, "gltf16_quad8.json")) as src:
        table = src.read()
    write("gltf16_quad8.json", table)
    pf, pb = PROBEFILTER, PROBEBENCH

    def filter_args(image, *extra):
        return ["filter", image, "--size", "16", *extra, "--out", path("out")]

    def reference(name, needles, data):
        f = write(name, data)
        expect_refused(name, [f, *needles], pf, "reference", f, "--size", "8", "--out", path("out"))

    # Radiance .hdr
    # A literal of 0 bytes: stb_image's loader loops on it forever.
    reference("zero-literal.hdr", ["literal of 0"], hdr(b"-Y 4 +X 8", rle_scanline(8, bytes([0x82, 7, 0]) + bytes(64))))
    reference("literal-past-width.hdr", ["literal of 128"], hdr(b"-Y 4 +X 8", rle_scanline(8, bytes([128]) + bytes(200))))
    reference("run-past-width.hdr", ["run of 100"], hdr(b"-Y 4 +X 8", rle_scanline(8, bytes([0x80 + 100, 1]) + bytes(64))))
    reference("huge-no-data.hdr", ["ends early"], hdr(b"-Y 8192 +X 16384"))
    reference("over-limit.hdr", ["over the limit"], hdr(b"-Y 20000 +X 40000"))
    reference("int-overflow.hdr", ["over the limit"], hdr(b"-Y 99999999999 +X 2"))
    reference("zero-size.hdr", ["zero size"], hdr(b"-Y 0 +X 0"))
    reference("negative-size.hdr", ["zero size"], hdr(b"-Y -4 +X 8"))
    reference("orientation.hdr", ["resolution line"], hdr(b"+Y 4 +X 8", bytes(4 * 32)))
    reference("no-format.hdr", ["FORMAT"], hdr(b"-Y 4 +X 8", bytes(4 * 32), header=b"#?RADIANCE\n\n"))
    reference("xyze.hdr", ["xyze"], hdr(b"-Y 4 +X 8", bytes(4 * 32), header=b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n"))
    reference("endless-header-line.hdr", ["header line"], b"#?RADIANCE\n" + b"x" * 100000)
    reference("endless-header.hdr", ["more than"], b"#?RADIANCE\n" + b"x\n" * 5000)
    flat_row = bytes([128, 128, 128, 128]) * 64
    reference("ten-of-32-rows.hdr", ["ends early"], hdr(b"-Y 32 +X 64", flat_row * 10))
    rle_row = rle_scanline(64, b"".join(bytes([0x80 + 64, v]) for v in (128, 128, 128, 128)))
    reference("rle-rows-missing.hdr", ["ends early"], hdr(b"-Y 32 +X 64", rle_row * 31))
    reference("rle-width-mismatch.hdr", ["says width 65"], hdr(b"-Y 32 +X 64", rle_scanline(65, bytes(200)) * 32))
    reference("bad-magic.hdr", ["#?RADIANCE"], b"#?SOMETHING\n" + bytes(64))

    # OpenEXR
    reference("huge-window.exr", ["over the limit"], exr_header(40000, 20000) + bytes(29000))
    reference("tiny-tiles.exr", ["tiles"], exr_header(16384, 8192, tiles=(1, 1)) + bytes(1000))
    reference("no-pixel-data.exr", ["EXR"], exr_header(2048, 1024))
    # OpenEXR goes by the version field's tiled flag: tiles without it would read as black scanlines.
    reference("tiles-without-flag.exr", ["tile description", "tiled flag"],
              exr_header(64, 32, tiles=(16, 16), tiled_flag=False) + bytes(512))
    reference("flag-without-tiles.exr", ["says tiled"], exr_header(64, 32, tiled_flag=True) + bytes(512))
    # A 2:1 data window cropped from a larger display window would be stretched over the sphere.
    reference("cropped-window.exr", ["data window (0, 0) to (63, 31)", "display window (0, 0) to (127, 127)"],
              exr_header(64, 32, display=(0, 0, 127, 127)) + bytes(512))
    many = tuple(b"C%03d" % k for k in range(128))
    reference("128-channels.exr", ["128 channels", "64"], exr_header(8192, 4096, channel_names=many) + bytes(1 << 20))
    reference("wrong-shape-huge.exr", ["aspect ratio 11584x11584"], exr_header(11584, 11584) + bytes(1 << 20))
    reference("wrong-shape-huge.hdr", ["aspect ratio 11584x11584"], hdr(b"-Y 11584 +X 11584", bytes(1 << 20)))
    reference("header-only.exr", ["EXR"], exr_header(64, 32)[:60])
    # A complete offset table whose chunks are not there: refused before the image's memory is taken.
    offsets = b"".join(struct.pack("<Q", 10**9 + k) for k in range(8192))
    reference("offsets-past-end.exr", ["EXR"], exr_header(16384, 8192) + offsets)
    header = exr_header(16384, 8192)
    offsets = struct.pack("<Q", len(header) + 8192 * 8) * 8192
    reference("offsets-one-chunk.exr", ["EXR"], header + offsets + bytes(64))
    # A probe is one flat image: the version field's multi-part and deep flags are refused before
    # OpenEXR reads the later headers or the per-pixel sample counts (a bomb in either takes GiBs).
    with open(path("good.exr"), "rb") as f:
        good = bytearray(f.read())
    version = struct.unpack_from("<i", good, 4)[0]
    for name, flag, needle in (("multi-part.exr", 0x1000, "multi-part"), ("deep.exr", 0x800, "deep")):
        struct.pack_into("<i", good, 4, version | flag)
        reference(name, [needle], bytes(good))

    # KTX2: a Zstandard level that promises an image at the pixel limit (1 GiB of RGBA16F) and holds
    # none of it, data that is not Zstandard, a level or offset past the end of the file, a format
    # that is not a float probe's, a cube array, a size over the limit.
    zstd_frame = bytes([0x28, 0xB5, 0x2F, 0xFD, 0x20, 0x00, 0x01, 0x00, 0x00])  # an empty raw block: no texels
    reference("zstd-bomb.ktx2", ["ends before its texels"], ktx2(97, 16384, 8192, 1, zstd_frame, scheme=2))
    reference("not-zstd.ktx2", ["Zstandard data is corrupt"], ktx2(97, 64, 32, 1, zlib.compress(bytes(64 * 32 * 8)), scheme=2))
    reference("level-past-end.ktx2", ["beyond the end"], ktx2(97, 16384, 8192, 1, bytes(64), stored=16384 * 8192 * 8))
    reference("huge-offset.ktx2", ["beyond the end"], ktx2(97, 8, 8, 6, bytes(3072), offset=2**63))
    reference("unorm.ktx2", ["VkFormat 37"], ktx2(37, 8, 8, 6, bytes(1536), texel_bytes=4))
    reference("cube-array.ktx2", ["array of 4 layers"], ktx2(97, 8, 8, 6, bytes(4 * 3072), layers=4))
    reference("over-limit.ktx2", ["over the limit"], ktx2(97, 40000, 40000, 6, b""))
    # A 2D image's metadata (read for its KTXorientation): past the end, over its limit, an entry past it.
    image = bytes(16 * 8 * 8)
    reference("metadata-past-end.ktx2", ["metadata lies beyond the end"], ktx2(97, 16, 8, 1, image, kvd=(10**9, 64)))
    reference("metadata-over-limit.ktx2", ["bytes of metadata, over the limit"], ktx2(97, 16, 8, 1, image, kvd=(104, 2**31)))
    entry = struct.pack("<I", 1000) + b"KTXorientation\0ru\0\0"
    reference("metadata-entry-past.ktx2", ["entry runs past the metadata"],
              ktx2(97, 16, 8, 1, image, kvd=(104 + len(image), len(entry)), tail=entry))

    # What a path names
    os.mkfifo(path("fifo.exr"))
    expect_refused("fifo-input", [path("fifo.exr"), "FIFO"], pf, "reference", path("fifo.exr"), "--size", "8", "--out", path("out"))
    os.mkdir(path("folder.exr"))
    expect_refused("folder-input", [path("folder.exr"), "folder"], pf, "reference", path("folder.exr"), "--size", "8", "--out",
                   path("out"))
    expect_refused("device-input", ["/dev/zero", "device"], pf, "reference", "/dev/zero", "--size", "8", "--out", path("out"))
    expect_refused("device-table", ["/dev/zero", "device"], pf, *filter_args(path("good.exr"), "--table", "/dev/zero"))
    expect_refused("fifo-table", [path("fifo.exr"), "FIFO"], pf, *filter_args(path("good.exr"), "--table", path("fifo.exr")))
    expect_refused("folder-table", [path("folder.exr"), "folder"], pf, *filter_args(path("good.exr"), "--table", path("folder.exr")))
    with open(path("huge-table.json"), "wb") as f:
        f.truncate(100 << 20)  # sparse: no disk used
    expect_refused("huge-table", [path("huge-table.json"), "over the limit"], pf,
                   *filter_args(path("good.exr"), "--table", path("huge-table.json")))
    expect_refused("device-scene", ["/dev/zero", "device"], pf, "run", "/dev/zero", "--out", path("out"))

    # Outputs: nothing but the tool's own output is replaced, no link is followed. All in outs/.
    o = lambda name: path(os.path.join("outs", name))
    os.makedirs(o("kept"))
    write("outs/kept/mine.txt", "not probefilter's")
    write("outs/precious.txt", "precious")
    for link, target in (("dangling", "nowhere"), ("loop", "loop"), ("folder-link", "kept"), ("file-link", "precious.txt")):
        os.symlink(target, o(link))
    os.mkfifo(o("fifo"))
    nodes = []
    try:
        os.mknod(o("node"), 0o600 | stat.S_IFCHR, os.makedev(1, 3))  # a private null device
        nodes = ["node"]
    except PermissionError:
        print("skip device-node outputs: mknod is not permitted here")
    os.makedirs(o("mounted/sub"))
    write("outs/mounted/report.json", '{"command": "filter"}')  # probefilter's own output, but for the mount
    mounted = os.environ.get("HOSTILE_PRIVATE_MOUNTS") == "1" and subprocess.run(
        ["mount", "-t", "tmpfs", "probe-test", o("mounted/sub")], capture_output=True).returncode == 0
    if mounted:
        write("outs/mounted/sub/theirs.txt", "another file system's")
    else:
        print("skip the mount inside an output folder: no private mount namespace here")
    scene = write("scene.json", '{"probes": [{"name": "sky", "image": "good.exr", "face_size": 16}], "materials": []}')
    folder_commands = {
        "filter": [pf, "filter", path("good.exr"), "--size", "16"],
        "reference": [pf, "reference", path("good.exr"), "--size", "8"],
        "run": [pf, "run", scene],
        "compare": [pb, "compare", path("good.exr"), "--size", "16", "--repeat", "1"],
        "sweep": [pb, "sweep", "--size", "16", "--synthetic", "sunsky", "--repeat", "1"],
    }
    links = ("dangling", "loop", "folder-link", "file-link")
    for command, args in folder_commands.items():
        for out in links + ("fifo", *nodes):
            needle = "symbolic link" if out in links else "not a folder"
            expect_refused(f"{command}-out-{out}", [o(out), needle], *args, "--out", o(out))
        if mounted:
            expect_refused(f"{command}-out-mount-inside", [o("mounted"), "mount point"], *args, "--out", o("mounted"))
    level_count = len(json.loads(table)["levels"])
    file_commands = {
        "synth": ([pf, "synth", "sky", "--size", "16", "--out"], ""),
        "probefit-fit": ([PROBEFIT, "fit", "--size", "16", "--levels", "3", "--taps", "4", "--form", "quad", "--out"], ".json"),
        "probefit-export": ([PROBEFIT, "export", path("gltf16_quad8.json"), "--out"], ".h"),
        "probefit-select": ([PROBEFIT, "select", path("gltf16_quad8.json"), "--out"], ".glsl"),
        "probefit-mix": ([PROBEFIT, "mix", *[path("gltf16_quad8.json")] * level_count, "--out"], ".json"),
    }
    for command, (args, extension) in file_commands.items():
        for out in links + ("kept", "fifo", *nodes):
            needle = "symbolic link" if out in links else "not a regular file"
            os.rename(o(out), o(out + extension))  # a prefix names PREFIX.json, .h, .glsl: one of them
            expect_refused(f"{command}-out-{out}", [o(out + extension), needle], *args, o(out))
            os.rename(o(out + extension), o(out))
    # An output folder that holds a folder the user cannot empty (as root: run as nobody, in a folder
    # of nobody's holding one of root's).
    as_user = []
    if os.geteuid() == 0:
        as_user = ["setpriv", "--reuid", "65534", "--regid", "65534", "--clear-groups"]
        os.chmod(work, 0o755)
        os.chmod(o(""), 0o755)
    os.makedirs(o("user/out/locked"))
    write("outs/user/out/report.json", '{"command": "filter"}')
    write("outs/user/out/locked/level_0.exr", "")
    if as_user:
        for folder in (o("user"), o("user/out")):
            os.chown(folder, 65534, 65534)
    os.chmod(o("user/out/locked"), 0o555)
    if as_user and shutil.which("setpriv") is None:
        print("skip the output that cannot be emptied: no setpriv to run as another user")
    else:
        expect_refused("filter-out-cannot-be-emptied", [o("user/out"), "cannot be emptied"], *as_user, pf, "filter", path("good.exr"),
                       "--size", "16", "--out", o("user/out"))
    os.chmod(o("user/out/locked"), 0o755)
    os.chmod(work, 0o700)

    # Links planted at every staging name (a file's old fixed name and the pattern a killed run
    # leaves; an output folder's staging name) are neither followed nor removed by any command: the
    # output is written beside them.
    table16 = path("gltf16_quad8.json")
    files = {
        "synth": ([pf, "synth", "sky", "--size", "16", "--out", o("probe.exr")], ["probe.exr"]),
        "probefit-fit": ([PROBEFIT, "fit", "--size", "16", "--levels", "3", "--taps", "4", "--form", "quad", "--iterations", "2",
                          "--starts", "1", "--no-full-eval", "--bank", "none", "--out", o("fit")], ["fit.json", "fit.h", "fit.glsl"]),
        "probefit-export": ([PROBEFIT, "export", table16, "--out", o("export")], ["export.json", "export.h", "export.glsl"]),
        "probefit-select": ([PROBEFIT, "select", table16, "--out", o("select")], ["select.json", "select.h", "select.glsl"]),
        "probefit-mix": ([PROBEFIT, "mix", *[table16] * level_count, "--out", o("mix")], ["mix.json", "mix.h", "mix.glsl"]),
    }
    folders = {
        "filter": [pf, "filter", path("good.exr"), "--size", "16"],
        "reference": [pf, "reference", path("good.exr"), "--size", "8"],
        "run": [pf, "run", scene],
        "compare": [pb, "compare", path("good.exr"), "--size", "16", "--table", table16, "--repeat", "1", "--cell", "16"],
        "sweep": [pb, "sweep", "--size", "16", "--synthetic", "sunsky", "--samples", "8", "--fis-bias", "0", "--pyramid", "bspline",
                  "--fis-maps", "cube", "--repeat", "1", "--tables", os.environ["PROBE_TABLES"]],
    }
    for name, (args, outputs) in files.items():
        for output in outputs + (["fit.resume.json"] if name == "probefit-fit" else []):  # the fit's checkpoint too
            for planted in (f".{output}.partial", f".{output}.0badf00d.partial"):
                os.symlink("precious.txt", o(planted))
    for name in folders:
        os.symlink("kept", o(".probefilter-%08x-1-0badf00d" % fnv1a(f"{name}-out".encode())))
    for name, (args, outputs) in files.items():
        expect_written(f"{name}-beside-planted-staging-links", args, [o(out) for out in outputs], o("precious.txt"))
    for name, args in folders.items():
        expect_written(f"{name}-beside-planted-staging-links", [*args, "--out", o(f"{name}-out")], [o(f"{name}-out/report.json")],
                       o("precious.txt"))
    with open(o("kept/mine.txt")) as f:
        if f.read() != "not probefilter's": print("FAIL the folder behind the planted staging links changed")
    if mounted:
        subprocess.run(["umount", o("mounted/sub")], check=True)
    shutil.rmtree(o(""))

    # Limits, checked before the work
    good = path("good.exr")
    expect_refused("samples-huge", ["--samples 1000000000", "65536"], pf, *filter_args(good, "--method", "fis", "--samples", "1000000000"))
    expect_refused("samples-zero", ["--samples 0"], pf, *filter_args(good, "--method", "fis", "--samples", "0"))
    expect_refused("fis-bias-nan", ["--fis-bias nan"], pf, *filter_args(good, "--method", "fis", "--fis-bias", "nan"))
    expect_refused("fis-bias-inf", ["--fis-bias inf"], pf, *filter_args(good, "--method", "fis", "--fis-bias", "inf"))
    expect_refused("fis-bias-huge", ["--fis-bias 1e+300"], pf, *filter_args(good, "--method", "fis", "--fis-bias", "1e300"))
    expect_refused("repeat-huge", ["--repeat 1000000", "1000"], pf, *filter_args(good, "--repeat", "1000000"))
    expect_refused("filter-size-65536", ["face size 65536", "2048"], pf, "filter", good, "--size", "65536", "--out", path("out"))
    # Several inputs: one batch, a folder each named after its input.
    os.makedirs(path("other"), exist_ok=True)
    shutil.copy(good, path("other/good.exr"))
    expect_refused("batch-same-name", ["same name", "good/"], pf, "filter", good, path("other/good.exr"), "--size", "16",
                   "--out", path("out"))
    expect_refused("batch-65-inputs", ["65 inputs", "64"], pf, "filter", *[good] * 65, "--size", "16", "--out", path("out"))
    expect_refused("batch-slices", ["--slices", "one input"], pf, "filter", good, path("other/good.exr"), "--size", "16", "--slices", "2",
                   "--out", path("out"))
    expect_refused("batch-bad-member", [path("bad-member.exr")], pf, "filter", good, write("bad-member.exr", b"not an exr"), "--size", "16",
                   "--out", path("out"))
    shutil.rmtree(path("other"))
    expect_refused("ktx2-unknown-format", ["--ktx2", "bc7"], pf, *filter_args(good, "--ktx2", "bc7"))
    # The exact reference is quadratic in the face size: over an hour's estimate is refused up front.
    expect_refused("reference-size-2048", ["reference at 2048^2 would take", "--allow-long"], pf, "reference", good, "--size", "2048",
                   "--out", path("out"))
    expect_refused("filter-against-reference-2048", ["reference at 2048^2 would take", "--allow-long"], pf, "filter", good, "--size",
                   "2048", "--method", "fis", "--against-reference", "--out", path("out"))
    # Settings the device cannot run are refused before the probe is read (on the test device,
    # lavapipe, a storage buffer holds at most 128 MiB: the reference's sums at 2048^2 need 512 MiB).
    # The input here is at the pixel limit, which takes 25 s and 1.5 GiB to read.
    shown = subprocess.run([pf, "filter", good, "--size", "16", "--out", path("device")], capture_output=True, text=True).stdout
    shutil.rmtree(path("device"))
    if "llvmpipe" in shown:
        huge = path("huge.exr")
        subprocess.run([pf, "synth", "sky", "--equirect", "16384", "--out", huge], check=True, capture_output=True)
        # The reference's sums (either sampling mode filters at 2048^2: tests/cli_largest_size.sh runs both).
        expect_refused("filter-2048-reference-over-device-range", ["maxStorageBufferRange", "2048^2"], pf, "filter", huge, "--size",
                       "2048", "--method", "reference", "--out", path("out"))
        os.remove(huge)
    else:
        print("skip the device's buffer range refusals: the test device is not lavapipe")
    expect_refused("reference-size-4096", ["face size 4096", "2048"], pf, "reference", good, "--size", "4096", "--out", path("out"))
    expect_refused("sweep-repeat", ["--repeat 1000000"], pb, "sweep", "--size", "16", "--repeat", "1000000", "--out", path("out"))
    expect_refused("sweep-samples", ["--samples 1000000000"], pb, "sweep", "--size", "16", "--samples", "1000000000", "--out",
                   path("out"))
    expect_refused("compare-samples", ["--samples 1000000000"], pb, "compare", good, "--size", "16", "--samples", "1000000000",
                   "--out", path("out"))
    for value in ("0", "-1", "nan", "inf", "1e+300"):
        expect_refused(f"compare-max-error-{value}", [f"--max-error {value}"], pb, "compare", good, "--size", "16", "--max-error", value,
                       "--out", path("out"))
    # Values that are empty or not UTF-8 (reports and tables are JSON, UTF-8 only), for any option.
    not_utf8 = os.fsdecode(b"in\xff.exr")
    shutil.copy(good, path(not_utf8))
    expect_refused("filter-input-not-utf8", ["input", "UTF-8"], pf, "filter", path(not_utf8), "--size", "16", "--out", path("out"))
    expect_refused("filter-out-not-utf8", ["--out", "UTF-8"], pf, "filter", good, "--size", "16", "--out", path(os.fsdecode(b"o\xff")))
    expect_refused("probefit-select-not-utf8", ["tables", "UTF-8"], PROBEFIT, "select", path(not_utf8), "--out", path("t"))
    for flag in ("--levels", "--fis-bias", "--table", "--out", "--size"):
        expect_refused(f"filter-empty{flag}", [flag, "empty value"], pf, *filter_args(good, flag, ""))
    expect_refused("filter-empty-input", ["input", "empty value"], pf, "filter", "", "--size", "16", "--out", path("out"))
    for flag in ("--levels", "--fit-levels", "--out", "--roughness"):
        expect_refused(f"probefit-empty{flag}", [flag, "empty value"], PROBEFIT, "fit", "--size", "16", "--taps", "4", "--form", "quad",
                       "--out", path("t"), flag, "")
    os.remove(path(not_utf8))
    expect_refused("compare-cell", ["--cell 100000"], pb, "compare", good, "--size", "16", "--cell", "100000", "--out", path("out"))
    expect_refused("compare-spheres", ["--roughness"], pb, "compare", good, "--size", "16", "--roughness", ",".join(["0.5"] * 1000),
                   "--out", path("out"))
    fit = [PROBEFIT, "fit", "--form", "quad", "--out", path("out")]
    expect_refused("probefit-size-4096", ["--size", "4096", "1024"], *fit, "--size", "4096", "--taps", "8")
    expect_refused("probefit-size-65536", ["--size", "65536"], *fit, "--size", "65536", "--taps", "8")
    expect_refused("probefit-taps-huge", ["--taps", "2147483644", "64"], *fit, "--size", "16", "--taps", "2147483644")

    # synth writes only what filter reads
    for width in ("3", "0", "-2", "1000000"):
        expect_refused(f"synth-equirect-{width}", [f"--equirect {width}"], pf, "synth", "sky", "--equirect", width, "--out",
                       path("out.exr"))
    expect_refused("synth-size", ["face size 3"], pf, "synth", "sky", "--size", "3", "--out", path("out.exr"))

    # JSON: tables
    def bad_table(name, needles, text):
        f = write(name, text)
        expect_refused(name + " (filter)", [f, *needles], pf, *filter_args(good, "--table", f))
        expect_refused(name + " (probefit eval)", [f, *needles], PROBEFIT, "eval", f)

    bad_table("deep.json", ["nested deeper"], '{"a": ' + "[" * 100000 + "]" * 100000 + "}")
    bad_table("deep-objects.json", ["nested deeper"], '{"a": ' + '{"b": ' * 100000 + "1" + "}" * 100000 + "}")
    bad_table("overflow-number.json", ["not valid JSON"], table.replace('"fitSeconds": ', '"fitSeconds": 1e999, "x": ', 1))
    bad_table("taps-overflow.json", ["tap count 2147483644"], table.replace('"taps": 8', '"taps": 2147483644', 1))
    bad_table("size-beyond-int.json", ["faceSize"], table.replace('"faceSize": 16', '"faceSize": 4294967312', 1))
    bad_table("size-fraction.json", ["faceSize"], table.replace('"faceSize": 16', '"faceSize": 16.5', 1))
    bad_table("budget-negative.json", ["stratifiedBudget", "-1"], re.sub(r'"stratifiedBudget": \d+', '"stratifiedBudget": -1', table))
    bad_table("duplicate-key.json", ["appears twice"], table.replace('"taps": 8', '"taps": 8, "taps": 8', 1))
    bad_table("unknown-field.json", ["unknown field 'shininess'"], table.replace('"taps": 8', '"taps": 8, "shininess": 3', 1))
    bad_table("truncated.json", ["not valid JSON"], table[: len(table) // 2])
    # Checked in time linear in the file: 400000 objects in one array (a quadratic check takes minutes).
    objects = ", ".join(["{}"] * 400000)
    bad_table("many-objects.json", ["unknown field 'x'"], table.replace('"taps": 8', '"taps": 8, "x": [%s]' % objects, 1))
    # At the text-file limit, a document of empty objects: a tree of 2 GiB, refused by its value count
    # before it is built.
    empties = '{"levels": [' + ",".join(["{}"] * ((64 << 20) // 3 - 10)) + "]}"
    bad_table("64MiB-of-objects.json", ["more than 1048576 values"], empties)
    f = write("64MiB-of-objects-scene.json", empties)
    expect_refused("64MiB-of-objects-scene.json", [f, "more than 1048576 values"], pf, "run", f, "--out", path("out"))
    os.makedirs(path("sweep-again"))
    write("sweep-again/report.json", empties)
    del empties  # a child's peak resident set starts from this process's, which it is forked from
    write("sweep-again/sweep.csv", "")
    expect_refused("sweep-summarize-empty-csv", [path("sweep-again/sweep.csv"), "header"], pb, "sweep", "--summarize",
                   path("sweep-again"), "--out", path("out"))
    os.remove(path("sweep-again/sweep.csv"))
    os.mkfifo(path("sweep-again/sweep.csv"))
    expect_refused("sweep-summarize-fifo-csv", [path("sweep-again/sweep.csv"), "FIFO"], pb, "sweep", "--summarize",
                   path("sweep-again"), "--out", path("out"))
    os.remove(path("sweep-again/sweep.csv"))
    expect_refused("out-with-64MiB-report", [path("sweep-again"), "holds no report.json of probefilter's"], pf,
                   *filter_args(good)[:-1], path("sweep-again"))
    shutil.rmtree(path("sweep-again"))
    bad_table("newline-key.json", ["unknown field 'line\\none'"], table.replace('"taps": 8', '"taps": 8, "line\\none": 1', 1))
    t = json.loads(table)
    t["levels"][2]["coefficients"][7] = 1e38
    bad_table("huge-coefficient.json", ["coefficient 7", "not a finite number"], json.dumps(t))
    t = json.loads(table)
    for level in t["levels"]:
        level["coefficients"] = [0.0] * len(level["coefficients"])
    bad_table("zero-weights.json", ["weights sum to"], json.dumps(t))
    t = json.loads(table)
    for level in t["levels"]:
        c = level["coefficients"]
        # Tap 1 of every frame cancels tap 0: weights (parameter 4, three coefficients) negated.
        for frame in range(3):
            for k in range(3):
                c[((frame * 8 + 1) * 5 + 4) * 3 + k] = -c[((frame * 8 + 0) * 5 + 4) * 3 + k]
                for tap in range(2, 8):
                    c[((frame * 8 + tap) * 5 + 4) * 3 + k] = 0.0
    bad_table("cancelling-weights.json", ["weights sum to"], json.dumps(t))

    # Published text layout
    def bad_text(name, needles, text):
        f = write(name, text)
        expect_refused(name, [f, *needles], pf, *filter_args(good, "--table", f, "--table-taps", "4", "--table-form", "quad"))

    count = 4 * 5 * 3 * 3 * 4  # levels x parameters x coefficients x frames x taps
    bad_text("nan.txt", ["not a finite number"], " ".join(["nan"] * count))
    bad_text("inf.txt", ["not a finite number"], " ".join(["inf"] * count))
    bad_text("zeros.txt", ["weights sum to"], " ".join(["0"] * count))
    bad_text("short.txt", ["numbers, expected"], " ".join(["1"] * (count - 1)))

    # JSON: scenes
    def bad_scene(name, needles, probe_fields, materials=""):
        text = '{"probes": [{"name": "sky", "image": "good.exr", %s}], "materials": [%s]}' % (probe_fields, materials)
        f = write(name, text)
        expect_refused(name, [f, *needles], pf, "run", f, "--out", path("out"))

    many = ", ".join('{"name": "m%d", "roughness": 0.5}' % k for k in range(2000))
    bad_scene("scene-many-materials.json", ["materials", "over the limit"], '"face_size": 16', many)
    bad_scene("scene-face-fraction.json", ["face_size", "16.5"], '"face_size": 16.5')
    bad_scene("scene-face-overflow.json", ["number overflow"], '"face_size": 1e999')
    bad_scene("scene-face-beyond-int.json", ["face_size"], '"face_size": 4294967312')
    bad_scene("scene-face-huge.json", ["face_size", "2048"], '"face_size": 65536')
    bad_scene("scene-samples-huge.json", ["samples"], '"samples": 1000000000, "method": "fis"')
    bad_scene("scene-duplicate-key.json", ["appears twice"], '"face_size": 16, "face_size": 32')
    bad_scene("scene-deep.json", ["nested deeper"], '"x": ' + "[" * 100000 + "]" * 100000)
    bad_scene("scene-deep-wrong-type.json", ["nested deeper"], '"face_size": ' + "[" * 100000 + "]" * 100000)
    bad_scene("scene-wrong-type.json", ["face_size", "array"], '"face_size": [[[[1]]]]')
    bad_scene("scene-many-objects.json", ["materials", "over the limit"], '"face_size": 16', ", ".join(["{}"] * 400000))
    f = write("scene-probe-report.json", '{"probes": [{"name": "report.json", "image": "good.exr", "face_size": 16}], "materials": []}')
    expect_refused("scene-probe-report.json", [f, "'report.json' is the name of one of the run's own files"], pf, "run", f, "--out",
                   path("out"))


if __name__ == "__main__":
    # A mount namespace of the suite's own, where it may mount a tmpfs that goes with it.
    if "HOSTILE_PRIVATE_MOUNTS" not in os.environ:
        private = subprocess.run(["unshare", "--mount", "--propagation", "private", "true"], capture_output=True).returncode == 0
        os.environ["HOSTILE_PRIVATE_MOUNTS"] = "1" if private else "0"
        if private: os.execvp("unshare", ["unshare", "--mount", "--propagation", "private", sys.executable, *sys.argv])
    try:
        main()
    finally:
        subprocess.run(["umount", os.path.join(work, "outs/mounted/sub")], capture_output=True)
        subprocess.run(["rm", "-rf", work])
    print(f"hostile_inputs: {refused} of {tried} bad inputs refused as required")
    sys.exit(0 if refused == tried else 1)
