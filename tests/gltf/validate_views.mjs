// The gallery's 3-D view copies (viewer/STEM.js: a .glb in base64, quantized
// and EXT_meshopt_compression-compressed) decoded with meshoptimizer's own
// JavaScript decoder, then checked by the Khronos glTF validator, which cannot
// read meshopt streams itself but checks everything else (KHR_mesh_quantization
// types, accessor bounds against the decoded data, index ranges).
// Usage: node validate_views.mjs VIEWER/STEM.js ... — prints each file's
// messages and sizes; exit 1 if any file has a message or fails to decode.
import validator from "gltf-validator";
import { MeshoptDecoder } from "meshoptimizer/decoder";
import fs from "fs";

await MeshoptDecoder.ready;

function glbFromScript(path) {
  const text = fs.readFileSync(path, "utf8");
  const m = text.match(/"([A-Za-z0-9+/=]+)"\);\s*$/);
  if (!m) throw new Error("no base64 .glb in the script");
  return new Uint8Array(Buffer.from(m[1], "base64"));
}

// The same .glb with every meshopt-compressed view decoded into one plain
// binary chunk, and the extension removed.
function decoded(glb) {
  const dv = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
  const jsonLen = dv.getUint32(12, true);
  const doc = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLen)));
  const binStart = 20 + jsonLen + 8;
  const bin = glb.subarray(binStart, binStart + dv.getUint32(20 + jsonLen, true));
  const parts = [];
  let offset = 0;
  for (const view of doc.bufferViews) {
    const ext = view.extensions && view.extensions.EXT_meshopt_compression;
    let bytes;
    if (ext) {
      const source = bin.subarray(ext.byteOffset, ext.byteOffset + ext.byteLength);
      bytes = new Uint8Array(ext.count * ext.byteStride);
      MeshoptDecoder.decodeGltfBuffer(bytes, ext.count, ext.byteStride, source, ext.mode, ext.filter || "NONE");
      delete view.extensions;
    } else {
      bytes = bin.subarray(view.byteOffset, view.byteOffset + view.byteLength);
    }
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = bytes.length;
    parts.push(bytes);
    offset = (offset + bytes.length + 3) & ~3;
    parts.push(new Uint8Array(offset - (view.byteOffset + bytes.length)));
  }
  doc.buffers = [{ byteLength: offset }];
  for (const key of ["extensionsUsed", "extensionsRequired"]) {
    doc[key] = doc[key].filter((e) => e !== "EXT_meshopt_compression");
  }
  let json = new TextEncoder().encode(JSON.stringify(doc));
  const jsonPad = (4 - (json.length % 4)) % 4;
  json = Uint8Array.from([...json, ...new Array(jsonPad).fill(0x20)]);
  const total = 12 + 8 + json.length + 8 + offset;
  const out = new Uint8Array(total);
  const o = new DataView(out.buffer);
  out.set([0x67, 0x6c, 0x54, 0x46]);
  o.setUint32(4, 2, true);
  o.setUint32(8, total, true);
  o.setUint32(12, json.length, true);
  o.setUint32(16, 0x4e4f534a, true);
  out.set(json, 20);
  o.setUint32(20 + json.length, offset, true);
  o.setUint32(24 + json.length, 0x004e4942, true);
  let at = 28 + json.length;
  for (const p of parts) { out.set(p, at); at += p.length; }
  return { out, doc };
}

let bad = 0;
for (const path of process.argv.slice(2)) {
  try {
    const glb = glbFromScript(path);
    const { out, doc } = decoded(glb);
    const report = await validator.validateBytes(out);
    const n = report.issues;
    const acc = doc.accessors;
    const triangles = acc[doc.meshes[0].primitives[0].indices].count / 3;
    console.log(`${path}: ${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints; `
      + `${acc[0].count} vertices, ${triangles} triangles, ${glb.length} bytes compressed, ${out.length} decoded`);
    for (const m of n.messages) console.log(`  ${m.code} ${m.pointer || ""} ${m.message}`);
    if (n.messages.length) bad++;
  } catch (e) {
    console.log(`${path}: could not be decoded: ${e.message}`);
    bad++;
  }
}
process.exit(bad ? 1 : 0);
