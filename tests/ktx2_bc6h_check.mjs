// Reads a BC6H probe.ktx2 with the independent parser ktx-parse and checks what an engine relies on:
// VK_FORMAT_BC6H_UFLOAT_BLOCK, a cube with every level, each level the six faces' 4x4 blocks (16
// bytes each, one block below 4x4), KTX-Software's descriptor for the format (colour model BC6H,
// 4x4 texel blocks, 16 bytes a plane, one 128-bit unsigned float sample) and the roughness metadata.
// Usage: node ktx2_bc6h_check.mjs BC6H.ktx2 REPORT.json
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { pathToFileURL } from "node:url";

const resolve = createRequire(process.env.KTX_PARSE_DIR + "/").resolve;
const { read, KHR_DF_TRANSFER_LINEAR, KHR_DF_SAMPLE_DATATYPE_FLOAT, KHR_DF_SAMPLE_DATATYPE_SIGNED } =
  await import(pathToFileURL(resolve("ktx-parse")).href);

const [path, reportPath] = process.argv.slice(2);
// khr_df.h's model numbers (ktx-parse names only some of them): BC1A 128 .. BC6H 133, BC7 134.
const VK_FORMAT_BC6H_UFLOAT_BLOCK = 143, KHR_DF_MODEL_BC6H = 133;
const report = JSON.parse(readFileSync(reportPath, "utf8"));
let failures = 0;
const check = (ok, what) => { if (!ok) { console.log(`FAIL ${what}`); failures++; } };
const text = (value) => typeof value === "string" ? value : new TextDecoder().decode(value ?? new Uint8Array()).replace(/\0$/, "");

const ktx = read(new Uint8Array(readFileSync(path)));
check(ktx.vkFormat === VK_FORMAT_BC6H_UFLOAT_BLOCK, `vkFormat ${ktx.vkFormat}`);
check(ktx.typeSize === 1, `typeSize ${ktx.typeSize}`);
check(ktx.faceCount === 6 && ktx.layerCount === 0 && ktx.pixelDepth === 0, "not a plain cube");
check(ktx.pixelWidth === report.face_size && ktx.pixelHeight === report.face_size, `size ${ktx.pixelWidth}`);
check(ktx.levels.length === report.level_count, `${ktx.levels.length} levels`);
const dfd = ktx.dataFormatDescriptor[0];
check(dfd.colorModel === KHR_DF_MODEL_BC6H && dfd.transferFunction === KHR_DF_TRANSFER_LINEAR, `colour model ${dfd.colorModel}`);
check(dfd.texelBlockDimension.join() === "3,3,0,0", `texel block ${dfd.texelBlockDimension}`);
check(dfd.bytesPlane[0] === 16, `bytesPlane0 ${dfd.bytesPlane[0]}`);
const sample = dfd.samples[0];
check(dfd.samples.length === 1 && sample.bitOffset === 0 && sample.bitLength === 127 &&
      (sample.channelType & KHR_DF_SAMPLE_DATATYPE_FLOAT) && !(sample.channelType & KHR_DF_SAMPLE_DATATYPE_SIGNED),
      `sample ${JSON.stringify(sample)}`);
ktx.levels.forEach((level, m) => {
  const across = Math.ceil(Math.max(1, report.face_size >> m) / 4);
  check(level.levelData.byteLength === 6 * across * across * 16, `level ${m} holds ${level.levelData.byteLength} bytes`);
  check(level.uncompressedByteLength === level.levelData.byteLength, `level ${m}: uncompressed length`);
});
check(text(ktx.keyValue["probefilter.mapping"]) === report.mapping, "mapping metadata");
check(report.ktx2.format === "bc6h" && report.ktx2.encode_gpu_ms > 0, `report ${JSON.stringify(report.ktx2)}`);
console.log(failures ? `${path}: ${failures} failure(s)` : `${path}: BC6H cube, ${ktx.levels.length} levels, as KTX-Software describes it`);
process.exit(failures ? 1 : 0);
