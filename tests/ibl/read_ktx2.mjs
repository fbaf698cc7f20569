// Reads a KTX2 file with ktx-parse (an independent, maintained reader) and prints what the
// tests check as JSON: header, data format descriptor, key/values, level sizes, and the
// centre texel of every face of every level (decoded from half or 32-bit floats).
// Usage: node read_ktx2.mjs KTX_PARSE_PACKAGE_DIR FILE.ktx2
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [packageDir, file] = process.argv.slice(2);
const manifest = JSON.parse(readFileSync(join(packageDir, 'package.json'), 'utf8'));
const entry = manifest.exports?.['.']?.default ?? manifest.module ?? manifest.main;
const { read } = await import(pathToFileURL(join(packageDir, entry)).href);

const container = read(new Uint8Array(readFileSync(file)));
const dfd = container.dataFormatDescriptor[0];
const channelBytes = container.typeSize;
const channels = dfd.samples.length;

function halfToFloat(h) {
  const s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 0x1f, m = h & 0x3ff;
  if (e === 0) return s * m * 2 ** -24;
  if (e === 31) return m ? NaN : s * Infinity;
  return s * (1 + m / 1024) * 2 ** (e - 15);
}

const levels = container.levels.map((level, mip) => {
  const size = Math.max(1, container.pixelWidth >> mip);
  const heightAt = Math.max(1, container.pixelHeight >> mip);
  const faceBytes = size * heightAt * channels * channelBytes;
  const view = new DataView(level.levelData.buffer, level.levelData.byteOffset, level.levelData.byteLength);
  const centres = [];
  for (let face = 0; face < container.faceCount; face++) {
    const texel = (Math.floor(heightAt / 2) * size + Math.floor(size / 2)) * channels;
    const value = [];
    for (let c = 0; c < channels; c++) {
      const at = face * faceBytes + (texel + c) * channelBytes;
      value.push(channelBytes === 2 ? halfToFloat(view.getUint16(at, true)) : view.getFloat32(at, true));
    }
    centres.push(value);
  }
  return { byteLength: level.levelData.byteLength, uncompressedByteLength: level.uncompressedByteLength, centres };
});

console.log(JSON.stringify({
  vkFormat: container.vkFormat, typeSize: container.typeSize,
  pixelWidth: container.pixelWidth, pixelHeight: container.pixelHeight, pixelDepth: container.pixelDepth,
  layerCount: container.layerCount, faceCount: container.faceCount, levelCount: container.levelCount,
  supercompressionScheme: container.supercompressionScheme,
  dfd: { colorModel: dfd.colorModel, colorPrimaries: dfd.colorPrimaries, transferFunction: dfd.transferFunction,
         bytesPlane0: dfd.bytesPlane[0],
         samples: dfd.samples.map(s => ({ bitOffset: s.bitOffset, bitLength: s.bitLength, channelType: s.channelType })) },
  orientation: container.keyValue.KTXorientation ?? null,
  levels,
}));
