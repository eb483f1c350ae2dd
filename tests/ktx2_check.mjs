// Reads probe.ktx2 files with the independent parser ktx-parse and checks what an engine relies on:
// an uncompressed RGBA16F/RGBA32F cube with every level, a linear RGBSDA float descriptor, the
// roughness metadata, finite non-negative texels, and half == float within half precision.
// Usage: node ktx2_check.mjs HALF.ktx2 FLOAT.ktx2 REPORT.json
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { pathToFileURL } from "node:url";

// ktx-parse 2 is an ES module, which Debian 12's Node.js (18) cannot require(): resolved in the
// installed folder, then imported.
const resolve = createRequire(process.env.KTX_PARSE_DIR + "/").resolve;
const { read, VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, KHR_DF_MODEL_RGBSDA,
        KHR_DF_TRANSFER_LINEAR, KHR_DF_SAMPLE_DATATYPE_FLOAT } = await import(pathToFileURL(resolve("ktx-parse")).href);

const [halfPath, floatPath, reportPath] = process.argv.slice(2);
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

function decode(path, expectedFormat) {
  const ktx = read(new Uint8Array(readFileSync(path)));
  const half = expectedFormat === VK_FORMAT_R16G16B16A16_SFLOAT;
  check(ktx.vkFormat === expectedFormat, `${path}: vkFormat ${ktx.vkFormat}`);
  check(ktx.typeSize === (half ? 2 : 4), `${path}: typeSize ${ktx.typeSize}`);
  check(ktx.faceCount === 6 && ktx.layerCount === 0 && ktx.pixelDepth === 0, `${path}: not a plain cube`);
  check(ktx.pixelWidth === report.face_size && ktx.pixelHeight === report.face_size, `${path}: size ${ktx.pixelWidth}`);
  check(ktx.levels.length === report.level_count, `${path}: ${ktx.levels.length} levels`);
  const dfd = ktx.dataFormatDescriptor[0];
  check(dfd.colorModel === KHR_DF_MODEL_RGBSDA && dfd.transferFunction === KHR_DF_TRANSFER_LINEAR, `${path}: colour model`);
  check(dfd.samples.length === 4 && dfd.samples.every((s) => s.channelType & KHR_DF_SAMPLE_DATATYPE_FLOAT), `${path}: samples`);
  check(text(ktx.keyValue["probefilter.mapping"]) === report.mapping, `${path}: mapping metadata`);
  const roughness = text(ktx.keyValue["probefilter.roughness"]).split(" ").map(Number);
  check(roughness.length === report.level_count &&
        roughness.every((r, m) => Math.abs(r - report.levels[m].roughness) < 1e-6), `${path}: roughness metadata`);
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

const halves = decode(halfPath, VK_FORMAT_R16G16B16A16_SFLOAT);
const floats = decode(floatPath, VK_FORMAT_R32G32B32A32_SFLOAT);
let texels = 0;
floats.forEach((level, m) => level.forEach((f, k) => {
  const h = halves[m][k];
  texels++;
  if (!(Number.isFinite(f) && f >= 0 && Number.isFinite(h))) { check(false, `level ${m} value ${k}: ${f} / ${h}`); return; }
  if (Math.abs(h - Math.min(f, 65504)) > Math.min(f, 65504) * 1e-3 + 1e-7) check(false, `level ${m} value ${k}: half ${h} float ${f}`);
}));
console.log(`ktx-parse: ${floats.length} levels, ${texels} values checked, ${failures} failure(s)`);
process.exit(failures ? 1 : 0);
