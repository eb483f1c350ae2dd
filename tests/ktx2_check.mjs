// Reads probe.ktx2 files with the independent parser ktx-parse and checks what an engine relies on:
// an uncompressed RGBA16F/RGBA32F/RGB9E5 cube with every level, a linear RGBSDA descriptor (four float
// samples, or RGB9E5's mantissas and shared exponent as KTX-Software describes them), the roughness
// metadata, finite non-negative texels, and half and RGB9E5 (decoded here by the Vulkan
// specification's formula) == float within their precision; and a Zstandard-supercompressed copy of
// HALF whose levels the zstd command decompresses to HALF's bytes.
// Usage: node ktx2_check.mjs HALF.ktx2 FLOAT.ktx2 E5.ktx2 HALF_ZSTD.ktx2 REPORT.json
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { pathToFileURL } from "node:url";

// ktx-parse 2 is an ES module, which Debian 12's Node.js (18) cannot require(): resolved in the
// installed folder, then imported.
const resolve = createRequire(process.env.KTX_PARSE_DIR + "/").resolve;
const { read, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, KHR_DF_MODEL_RGBSDA,
        KHR_DF_TRANSFER_LINEAR, KHR_DF_SAMPLE_DATATYPE_FLOAT } = await import(pathToFileURL(resolve("ktx-parse")).href);

const [halfPath, floatPath, e5Path, zstdPath, reportPath] = process.argv.slice(2);
const VK_FORMAT_E5B9G9R9_UFLOAT_PACK32 = 123, KHR_DF_SAMPLE_DATATYPE_EXPONENT = 0x20;
const report = JSON.parse(readFileSync(reportPath, "utf8"));
let failures = 0;
const check = (ok, what) => { if (!ok) { console.log(`FAIL ${what}`); failures++; } };

function halfToFloat(h) {
  const s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 0x1f, m = h & 0x3ff;
  if (e === 0) return s * m * 2 ** -24;
  if (e === 31) return m ? NaN : s * Infinity;
  return s * (1 + m / 1024) * 2 ** (e - 15);
}

// ktx-parse decodes only the KTX-defined keys; others come as NUL-terminated bytes.
const text = (value) => typeof value === "string" ? value : new TextDecoder().decode(value ?? new Uint8Array()).replace(/\0$/, "");

// The container, its descriptor's header and the metadata, as every format has them.
function readCube(path, expectedFormat, typeSize) {
  const ktx = read(new Uint8Array(readFileSync(path)));
  check(ktx.vkFormat === expectedFormat, `${path}: vkFormat ${ktx.vkFormat}`);
  check(ktx.typeSize === typeSize, `${path}: typeSize ${ktx.typeSize}`);
  check(ktx.faceCount === 6 && ktx.layerCount === 0 && ktx.pixelDepth === 0, `${path}: not a plain cube`);
  check(ktx.pixelWidth === report.face_size && ktx.pixelHeight === report.face_size, `${path}: size ${ktx.pixelWidth}`);
  check(ktx.levels.length === report.level_count, `${path}: ${ktx.levels.length} levels`);
  const dfd = ktx.dataFormatDescriptor[0];
  check(dfd.colorModel === KHR_DF_MODEL_RGBSDA && dfd.transferFunction === KHR_DF_TRANSFER_LINEAR, `${path}: colour model`);
  check(text(ktx.keyValue["probefilter.mapping"]) === report.mapping, `${path}: mapping metadata`);
  const roughness = text(ktx.keyValue["probefilter.roughness"]).split(" ").map(Number);
  check(roughness.length === report.level_count &&
        roughness.every((r, m) => Math.abs(r - report.levels[m].roughness) < 1e-6), `${path}: roughness metadata`);
  return ktx;
}

function decode(path, expectedFormat) {
  const half = expectedFormat === VK_FORMAT_R16G16B16A16_SFLOAT;
  const ktx = readCube(path, expectedFormat, half ? 2 : 4);
  check(ktx.dataFormatDescriptor[0].samples.length === 4 &&
        ktx.dataFormatDescriptor[0].samples.every((s) => s.channelType & KHR_DF_SAMPLE_DATATYPE_FLOAT), `${path}: samples`);
  return ktx.levels.map((level, m) => {
    const size = Math.max(1, report.face_size >> m);
    const bytes = level.levelData;
    check(bytes.byteLength === 6 * size * size * 4 * (half ? 2 : 4), `${path}: level ${m} holds ${bytes.byteLength} bytes`);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const values = [];
    for (let k = 0; k < bytes.byteLength / (half ? 2 : 4); k++)
      values.push(half ? halfToFloat(view.getUint16(2 * k, true)) : view.getFloat32(4 * k, true));
    return values;
  });
}

// RGB9E5: R, G, B as 9-bit mantissas at bits 0, 9 and 18 sharing the 5-bit exponent at bit 27,
// value = mantissa * 2^(exponent - 15 - 9); a channel's mantissa sample and its exponent sample.
function decodeE5(path) {
  const ktx = readCube(path, VK_FORMAT_E5B9G9R9_UFLOAT_PACK32, 4);
  const samples = ktx.dataFormatDescriptor[0].samples;
  const expected = [0, 1, 2].flatMap((c) => [
    { bitOffset: 9 * c, bitLength: 8, channelType: c, sampleLower: 0, sampleUpper: 8448 },
    { bitOffset: 27, bitLength: 4, channelType: c | KHR_DF_SAMPLE_DATATYPE_EXPONENT, sampleLower: 15, sampleUpper: 31 }]);
  check(samples.length === 6 && expected.every((e, k) => Object.entries(e).every(([key, v]) => samples[k][key] === v)),
        `${path}: samples ${JSON.stringify(samples)}`);
  return ktx.levels.map((level, m) => {
    const size = Math.max(1, report.face_size >> m);
    const bytes = level.levelData;
    check(bytes.byteLength === 6 * size * size * 4, `${path}: level ${m} holds ${bytes.byteLength} bytes`);
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const values = [];
    for (let t = 0; t < bytes.byteLength / 4; t++) {
      const v = view.getUint32(4 * t, true), scale = 2 ** ((v >>> 27) - 24);
      values.push((v & 511) * scale, ((v >>> 9) & 511) * scale, ((v >>> 18) & 511) * scale);
    }
    return values;
  });
}

const halves = decode(halfPath, VK_FORMAT_R16G16B16A16_SFLOAT);
const floats = decode(floatPath, VK_FORMAT_R32G32B32A32_SFLOAT);
let texels = 0;
floats.forEach((level, m) => level.forEach((f, k) => {
  const h = halves[m][k];
  texels++;
  if (!(Number.isFinite(f) && f >= 0 && Number.isFinite(h))) { check(false, `level ${m} value ${k}: ${f} / ${h}`); return; }
  if (Math.abs(h - Math.min(f, 65504)) > Math.min(f, 65504) * 1e-3 + 1e-7) check(false, `level ${m} value ${k}: half ${h} float ${f}`);
}));
// RGB9E5 within half a step of its shared exponent: 2^-9 of the texel's brightest channel.
const e5 = decodeE5(e5Path);
floats.forEach((level, m) => {
  for (let t = 0; 4 * t < level.length; t++) {
    const rgb = [0, 1, 2].map((c) => Math.min(Math.max(level[4 * t + c], 0), 65408));
    const step = Math.max(...rgb) / 512 + 1e-7;
    rgb.forEach((f, c) => {
      const d = e5[m][3 * t + c];
      if (!(Math.abs(d - f) <= step)) check(false, `level ${m} texel ${t}: rgb9e5 ${d} float ${f}`);
    });
  }
});
// Supercompression scheme 2: each level, decompressed by the zstd command, is HALF's level.
const plain = read(new Uint8Array(readFileSync(halfPath))), packed = read(new Uint8Array(readFileSync(zstdPath)));
check(packed.supercompressionScheme === 2 && plain.supercompressionScheme === 0, `${zstdPath}: scheme ${packed.supercompressionScheme}`);
check(packed.levels.length === plain.levels.length, `${zstdPath}: ${packed.levels.length} levels`);
packed.levels.forEach((level, m) => {
  const unpacked = execFileSync("zstd", ["-d", "-c"], { input: level.levelData });
  check(level.uncompressedByteLength === unpacked.length && Buffer.compare(unpacked, Buffer.from(plain.levels[m].levelData)) === 0,
        `${zstdPath}: level ${m} does not decompress to the uncompressed file's`);
  check(level.levelData.byteLength < unpacked.length || unpacked.length < 64, `${zstdPath}: level ${m} is not smaller`);
});
console.log(`ktx-parse: ${floats.length} levels, ${texels} values checked, ${failures} failure(s)`);
process.exit(failures ? 1 : 0);
