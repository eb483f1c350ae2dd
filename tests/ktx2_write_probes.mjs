// Writes KTX2 probes with the independent writer ktx-parse, each beside the RGBA32F file of the
// values it holds, decoded here by the formats' definitions (Vulkan specification, "Numeric
// Representation and Computation"): probefilter must read both as the same probe.
//   cube_<format>.ktx2 / cube_<format>_expected.ktx2   8^2 cube, texels of random bits
//   column.ktx2                                        the expected RGBA16F cube's bytes as a 2D 8 x 48 image (1:6)
//   equirect_up.ktx2 / equirect_up_expected.ktx2       16 x 8 RGBA16F, rows stored bottom to top (KTXorientation "ru")
// Usage: node ktx2_write_probes.mjs OUT_DIR
import { writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { pathToFileURL } from "node:url";

const resolve = createRequire(process.env.KTX_PARSE_DIR + "/").resolve;
const ktx = await import(pathToFileURL(resolve("ktx-parse")).href);
const out = process.argv[2];

// A fixed sequence, so that a failure can be reproduced.
let state = 12345;
const random = () => (state = (Math.imul(state, 1103515245) + 12345) >>> 0) / 2 ** 32;
const bits = (n) => Math.floor(random() * 2 ** n);

const halfToFloat = (h) => {
  const e = (h >> 10) & 31, m = h & 1023;
  return e === 0 ? m * 2 ** -24 : (1 + m / 1024) * 2 ** (e - 15);
};
const smallFloat = (v, mantissaBits) => {
  const e = v >> mantissaBits, m = v & ((1 << mantissaBits) - 1);
  return e === 0 ? m * 2 ** (-14 - mantissaBits) : (1 + m / 2 ** mantissaBits) * 2 ** (e - 15);
};
// Finite, non-negative encodings: exponents below the all-ones that means Inf and NaN.
const randomHalf = () => (Math.min(bits(5), 29) << 10) | bits(10);
const randomSmall = (mantissaBits) => (Math.min(bits(5), 30) << mantissaBits) | bits(mantissaBits);

// Each format: bytes a texel, and a function that writes one random texel at a DataView offset and
// returns its R, G, B.
const formats = {
  rgba16f: [ktx.VK_FORMAT_R16G16B16A16_SFLOAT, 2, 8, (view, o) => {
    const c = [randomHalf(), randomHalf(), randomHalf()];
    c.forEach((h, k) => view.setUint16(o + 2 * k, h, true));
    view.setUint16(o + 6, 0x3c00, true);
    return c.map(halfToFloat);
  }],
  rgb16f: [ktx.VK_FORMAT_R16G16B16_SFLOAT, 2, 6, (view, o) => {
    const c = [randomHalf(), randomHalf(), randomHalf()];
    c.forEach((h, k) => view.setUint16(o + 2 * k, h, true));
    return c.map(halfToFloat);
  }],
  rgb32f: [ktx.VK_FORMAT_R32G32B32_SFLOAT, 4, 12, (view, o) => {
    const c = [random() * 100, random(), random() * 1e-3].map(Math.fround);
    c.forEach((v, k) => view.setFloat32(o + 4 * k, v, true));
    return c;
  }],
  b10g11r11: [ktx.VK_FORMAT_B10G11R11_UFLOAT_PACK32, 4, 4, (view, o) => {
    const r = randomSmall(6), g = randomSmall(6), b = randomSmall(5);
    view.setUint32(o, (r | (g << 11) | (b << 22)) >>> 0, true);
    return [smallFloat(r, 6), smallFloat(g, 6), smallFloat(b, 5)];
  }],
  e5b9g9r9: [ktx.VK_FORMAT_E5B9G9R9_UFLOAT_PACK32, 4, 4, (view, o) => {
    const r = bits(9), g = bits(9), b = bits(9), e = bits(5);
    view.setUint32(o, (r | (g << 9) | (b << 18) | (e << 27)) >>> 0, true);
    return [r, g, b].map((m) => m * 2 ** (e - 15 - 9));
  }],
};

function container(vkFormat, typeSize, width, height, faceCount, data, keyValue = {}) {
  const c = ktx.createDefaultContainer();
  Object.assign(c, { vkFormat, typeSize, pixelWidth: width, pixelHeight: height, faceCount, levelCount: 1, keyValue });
  c.dataFormatDescriptor[0].colorModel = ktx.KHR_DF_MODEL_RGBSDA;
  c.dataFormatDescriptor[0].transferFunction = ktx.KHR_DF_TRANSFER_LINEAR;
  c.levels = [{ levelData: data, uncompressedByteLength: data.byteLength }];
  return ktx.write(c);
}

// RGBA32F bytes of a list of RGB texels, alpha 1.
function rgba32f(texels) {
  const data = new Float32Array(4 * texels.length);
  texels.forEach((c, t) => data.set([...c, 1], 4 * t));
  return new Uint8Array(data.buffer);
}

// `count` random texels in a format: its bytes and the RGB they decode to.
function randomTexels(format, count) {
  const [, , bytes, texel] = formats[format];
  const data = new Uint8Array(bytes * count), view = new DataView(data.buffer), rgb = [];
  for (let t = 0; t < count; ++t) rgb.push(texel(view, bytes * t));
  return { data, rgb };
}

const size = 8, cubeTexels = 6 * size * size;
for (const format of Object.keys(formats)) {
  const [vkFormat, typeSize] = formats[format], { data, rgb } = randomTexels(format, cubeTexels);
  writeFileSync(`${out}/cube_${format}.ktx2`, container(vkFormat, typeSize, size, size, 6, data));
  writeFileSync(`${out}/cube_${format}_expected.ktx2`, container(ktx.VK_FORMAT_R32G32B32A32_SFLOAT, 4, size, size, 6, rgba32f(rgb)));
  if (format === "rgba16f") writeFileSync(`${out}/column.ktx2`, container(vkFormat, typeSize, size, 6 * size, 1, data));
}

// Rows bottom to top: the expected file holds them top to bottom.
const width = 16, height = 8, { data, rgb } = randomTexels("rgba16f", width * height);
const [vkFormat, typeSize] = formats.rgba16f;
writeFileSync(`${out}/equirect_up.ktx2`, container(vkFormat, typeSize, width, height, 1, data, { KTXorientation: "ru" }));
const upright = [];
for (let y = height - 1; y >= 0; --y) upright.push(...rgb.slice(y * width, (y + 1) * width));
writeFileSync(`${out}/equirect_up_expected.ktx2`, container(ktx.VK_FORMAT_R32G32B32A32_SFLOAT, 4, width, height, 1, rgba32f(upright)));
