// The reference reader and writer for canopy's ros2 module: Foxglove's own MCAP and ROS 2 CDR
// libraries (pinned in package-lock.json beside this file), run by Node.
//
//   node foxglove_reference.mjs dump FILE.mcap OUT.json   read FILE with Foxglove's indexed and
//        streaming readers, decode every message from its ros2msg schema, encode it again, and
//        write what was found (every value; byte fields as length and CRC-32) as JSON
//   node foxglove_reference.mjs write DIR                 write DIR/foxglove_{lz4,zstd,plain}.mcap
//        with Foxglove's writer, and DIR/foxglove_expected.json: what they hold
//
// canopy's tests (tests/ros2/mcap_reader_foxglove_test.cpp) run both and compare. Any failure
// exits with code 1 and a line on stderr.

import { open, writeFile, readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import { McapIndexedReader, McapStreamReader, McapWriter } from "@mcap/core";
import { FileHandleReadable, FileHandleWritable } from "@mcap/nodejs";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";

const require = createRequire(import.meta.url);
// Installed with @mcap/support (its zstd and lz4 decoders), pinned by the same lockfile.
const zstd = require("@foxglove/wasm-zstd");
const lz4Decompress = require("@foxglove/wasm-lz4");

// --- CRC-32 (ISO-HDLC), to summarise byte fields ----------------------------------------------
const CRC_TABLE = new Uint32Array(256).map((_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (let i = 0; i < bytes.length; i++) c = CRC_TABLE[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

// Decoded values as JSON: bytes as {bytes, crc32}, other typed arrays as arrays, numbers that
// JSON cannot hold (NaN, infinities) as strings, bigints as strings.
function jsonify(v) {
  if (v instanceof Uint8Array || v instanceof Int8Array) return { bytes: v.length, crc32: crc32(v) };
  if (ArrayBuffer.isView(v)) return Array.from(v, jsonify);
  if (Array.isArray(v)) return v.map(jsonify);
  if (typeof v === "bigint") return v.toString();
  if (typeof v === "number" && !Number.isFinite(v)) return String(v);
  if (v && typeof v === "object") {
    const out = {};
    for (const [k, x] of Object.entries(v)) out[k] = jsonify(x);
    return out;
  }
  return v;
}

function equalBytes(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

async function dump(file, outJson) {
  const decompressHandlers = await loadDecompressHandlers();
  const handle = await open(file, "r");
  const out = { file, messages: [] };
  try {
    const reader = await McapIndexedReader.Initialize({
      readable: new FileHandleReadable(handle),
      decompressHandlers,
    });
    out.header = { profile: reader.header.profile, library: reader.header.library };
    out.statistics = jsonify(reader.statistics ?? null);
    out.chunk_count = reader.chunkIndexes.length;
    out.chunk_compressions = [...new Set(reader.chunkIndexes.map((c) => c.compression))];
    out.channels = [...reader.channelsById.values()].map((c) => ({
      id: c.id,
      topic: c.topic,
      schema: reader.schemasById.get(c.schemaId)?.name ?? "",
      schema_encoding: reader.schemasById.get(c.schemaId)?.encoding ?? "",
      message_encoding: c.messageEncoding,
    }));
    const codecs = new Map();
    for await (const m of reader.readMessages()) {
      const channel = reader.channelsById.get(m.channelId);
      const schema = reader.schemasById.get(channel.schemaId);
      if (!codecs.has(schema.id)) {
        const definitions = parse(new TextDecoder().decode(schema.data), { ros2: true });
        codecs.set(schema.id, { reader: new MessageReader(definitions), writer: new MessageWriter(definitions) });
      }
      const { reader: decoder, writer: encoder } = codecs.get(schema.id);
      const value = decoder.readMessage(m.data);
      out.messages.push({
        topic: channel.topic,
        schema: schema.name,
        log_time: m.logTime.toString(),
        publish_time: m.publishTime.toString(),
        sequence: m.sequence,
        size: m.data.length,
        reencoded_equal: equalBytes(encoder.writeMessage(value), m.data),
        value: jsonify(value),
      });
    }
  } finally {
    await handle.close();
  }
  // The streaming reader too: every record in file order, chunk CRCs checked.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(await readFile(file));
  const counts = {};
  for (let r; (r = stream.nextRecord()); ) counts[r.type] = (counts[r.type] ?? 0) + 1;
  if (!stream.done()) throw new Error("the streaming reader did not reach the end of the file");
  out.stream_record_counts = counts;
  await writeFile(outJson, JSON.stringify(out, null, 1));
}

// --- An LZ4 frame compressor (Foxglove's libraries only decompress LZ4) ------------------------
// The frame: magic, FLG (version 1, independent blocks), BD (64 KiB blocks), header checksum
// (second byte of XXH32 of FLG and BD), blocks (compressed, or stored with the size's top bit),
// end mark. Blocks: greedy matches found through a hash of 4-byte sequences.
function xxh32(bytes, seed = 0) {
  const P1 = 2654435761, P2 = 2246822519, P3 = 3266489917, P4 = 668265263, P5 = 374761393;
  const rotl = (x, r) => ((x << r) | (x >>> (32 - r))) >>> 0;
  if (bytes.length >= 16) throw new Error("xxh32 here hashes frame descriptors only");
  let h = (seed + P5 + bytes.length) >>> 0;
  let i = 0;
  for (; i + 4 <= bytes.length; i += 4) {
    const w = (bytes[i] | (bytes[i + 1] << 8) | (bytes[i + 2] << 16) | (bytes[i + 3] << 24)) >>> 0;
    h = Math.imul(rotl((h + Math.imul(w, P3)) >>> 0, 17), P4) >>> 0;
  }
  for (; i < bytes.length; i++) h = Math.imul(rotl((h + Math.imul(bytes[i], P5)) >>> 0, 11), P1) >>> 0;
  h = Math.imul(h ^ (h >>> 15), P2) >>> 0;
  h = Math.imul(h ^ (h >>> 13), P3) >>> 0;
  return (h ^ (h >>> 16)) >>> 0;
}

function lz4Block(src) {
  const out = [];
  const n = src.length;
  const table = new Int32Array(1 << 16).fill(-1);
  const read32 = (p) => (src[p] | (src[p + 1] << 8) | (src[p + 2] << 16) | (src[p + 3] << 24)) >>> 0;
  const putLength = (len) => {
    for (; len >= 255; len -= 255) out.push(255);
    out.push(len);
  };
  const sequence = (anchor, end, offset, matchLength) => {
    const literals = end - anchor;
    const token = (Math.min(literals, 15) << 4) | (matchLength === undefined ? 0 : Math.min(matchLength - 4, 15));
    out.push(token);
    if (literals >= 15) putLength(literals - 15);
    for (let k = anchor; k < end; k++) out.push(src[k]);
    if (matchLength === undefined) return;
    out.push(offset & 0xff, offset >>> 8);
    if (matchLength - 4 >= 15) putLength(matchLength - 4 - 15);
  };
  let anchor = 0;
  let i = 0;
  const lastMatchStart = n - 12; // a match starts at least 12 bytes before the end
  const matchEnd = n - 5; // the last 5 bytes are literals
  while (i < lastMatchStart) {
    const word = read32(i);
    const h = Math.imul(word, 2654435761) >>> 16;
    const ref = table[h];
    table[h] = i;
    if (ref >= 0 && i - ref <= 65535 && read32(ref) === word) {
      let len = 4;
      while (i + len < matchEnd && src[ref + len] === src[i + len]) len++;
      sequence(anchor, i, i - ref, len);
      i += len;
      anchor = i;
    } else {
      i++;
    }
  }
  sequence(anchor, n);
  return Uint8Array.from(out);
}

function lz4Frame(data) {
  const parts = [];
  const flg = 0x60, bd = 0x40;
  parts.push(Uint8Array.from([0x04, 0x22, 0x4d, 0x18, flg, bd, (xxh32(Uint8Array.from([flg, bd])) >>> 8) & 0xff]));
  const u32 = (v) => Uint8Array.from([v & 0xff, (v >>> 8) & 0xff, (v >>> 16) & 0xff, (v >>> 24) & 0xff]);
  for (let at = 0; at < data.length; at += 65536) {
    const block = data.subarray(at, Math.min(at + 65536, data.length));
    const packed = lz4Block(block);
    if (packed.length < block.length) {
      parts.push(u32(packed.length), packed);
    } else {
      parts.push(u32((block.length | 0x80000000) >>> 0), block);
    }
  }
  parts.push(u32(0));
  const out = new Uint8Array(parts.reduce((s, p) => s + p.length, 0));
  let pos = 0;
  for (const p of parts) {
    out.set(p, pos);
    pos += p.length;
  }
  // Checked with Foxglove's own LZ4 decoder before it goes into a file.
  if (!equalBytes(lz4Decompress(out, data.length), data)) throw new Error("the test's LZ4 frame does not decode");
  return out;
}

// --- Writing with Foxglove's writer -----------------------------------------------------------
// ROS 2 Humble definitions, written here on their own (not canopy's texts).
const SEP = "=".repeat(80);
const TIME = `${SEP}\nMSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n`;
const HEADER = `${SEP}\nMSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n`;
const SCHEMAS = {
  "sensor_msgs/msg/Image":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data\n" +
    HEADER + TIME,
  "sensor_msgs/msg/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data\n" + HEADER + TIME,
  "sensor_msgs/msg/CameraInfo":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n" +
    "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nRegionOfInterest roi\n" + HEADER + TIME +
    `${SEP}\nMSG: sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n`,
  "tf2_msgs/msg/TFMessage":
    "geometry_msgs/TransformStamped[] transforms\n" +
    `${SEP}\nMSG: geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\nTransform transform\n` +
    HEADER + TIME +
    `${SEP}\nMSG: geometry_msgs/Transform\nVector3 translation\nQuaternion rotation\n` +
    `${SEP}\nMSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n` +
    `${SEP}\nMSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n`,
};

const W = 8, H = 6, FRAMES = 5;
const T0 = 1700000000n * 1000000000n + 250000000n;
const stampOf = (t) => ({ sec: Number(t / 1000000000n), nanosec: Number(t % 1000000000n) });
const b64 = (u8) => Buffer.from(u8.buffer, u8.byteOffset, u8.byteLength).toString("base64");
// A 1x1 PNG (one green pixel): what a RealSense's compressed topic carries, in small.
const PNG = Uint8Array.from(
  Buffer.from(
    "89504e470d0a1a0a0000000d4948445200000001000000010802000000907753de0000000c4944415408d763f8cf" +
      "c000000301010018dd8db00000000049454e44ae426082",
    "hex",
  ),
);

function messages() {
  const out = [];
  const tf = (t, parent, child, x, yaw) => ({
    header: { stamp: stampOf(t), frame_id: parent },
    child_frame_id: child,
    transform: {
      translation: { x, y: 0.5, z: 0.25 },
      rotation: { x: 0, y: 0, z: Math.sin(yaw / 2), w: Math.cos(yaw / 2) },
    },
  });
  out.push({
    topic: "/tf_static",
    schema: "tf2_msgs/msg/TFMessage",
    t: T0,
    value: {
      transforms: [
        tf(T0, "tool0", "camera_link", 0.05, 0),
        tf(T0, "camera_link", "camera_color_optical_frame", 0.0, -Math.PI / 2),
      ],
    },
  });
  for (let i = 0; i < FRAMES; i++) {
    const t = T0 + BigInt(i) * 100000000n;
    out.push({
      topic: "/tf",
      schema: "tf2_msgs/msg/TFMessage",
      t,
      value: { transforms: [tf(t, "world", "base_link", 0.1 * i, 0.05 * i), tf(t, "base_link", "tool0", 0.3, 0.01 * i)] },
    });
    // A depth image: 16UC1 in millimetres (0: no return), 32FC1 in metres (NaN: no return).
    const depth = (topic, frame, encoding, pixels) => ({
      topic,
      schema: "sensor_msgs/msg/Image",
      t,
      value: {
        header: { stamp: stampOf(t), frame_id: frame },
        height: H, width: W, encoding, is_bigendian: 0, step: W * pixels.BYTES_PER_ELEMENT,
        data: new Uint8Array(pixels.buffer),
      },
    });
    const mm = new Uint16Array(W * H).map((_, k) => (k % 7 === 0 ? 0 : 400 + 10 * k + i));
    out.push(depth("/camera/depth/image_rect_raw", "camera_depth_optical_frame", "16UC1", mm));
    const metres = new Float32Array(W * H).map((_, k) => (k % 5 === 0 ? NaN : 0.4 + 0.01 * k + 0.001 * i));
    out.push(depth("/camera/aligned_depth_to_color/image_raw", "camera_color_optical_frame", "32FC1", metres));
    out.push({
      topic: "/camera/color/image_raw/compressed",
      schema: "sensor_msgs/msg/CompressedImage",
      t: t + 1000000n,
      value: { header: { stamp: stampOf(t + 1000000n), frame_id: "camera_color_optical_frame" }, format: "png", data: PNG },
    });
    out.push({
      topic: "/camera/color/camera_info",
      schema: "sensor_msgs/msg/CameraInfo",
      t,
      value: {
        header: { stamp: stampOf(t), frame_id: "camera_color_optical_frame" },
        height: H, width: W, distortion_model: "plumb_bob",
        d: [0.1, -0.2, 0.001, 0.002, 0.0],
        k: [6.5, 0, 3.5, 0, 6.25, 2.5, 0, 0, 1],
        r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
        p: [6.5, 0, 3.5, 0, 0, 6.25, 2.5, 0, 0, 0, 1, 0],
        binning_x: 0, binning_y: 0,
        roi: { x_offset: 1, y_offset: 2, height: 3, width: 4, do_rectify: false },
      },
    });
  }
  return out;
}

async function writeOne(path, compression, all) {
  const handle = await open(path, "w");
  const options = { writable: new FileHandleWritable(handle), chunkSize: 600 };
  if (compression === "lz4") options.compressChunk = (data) => ({ compression: "lz4", compressedData: lz4Frame(data) });
  if (compression === "zstd") options.compressChunk = (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) });
  if (compression === "plain") options.useChunks = false;
  const writer = new McapWriter(options);
  await writer.start({ profile: "ros2", library: "foxglove-reference (@mcap/core 2.2.2)" });
  const channels = new Map();
  const writers = new Map();
  for (const m of all) {
    if (!channels.has(m.topic)) {
      const schemaId = await writer.registerSchema({
        name: m.schema,
        encoding: "ros2msg",
        data: new TextEncoder().encode(SCHEMAS[m.schema]),
      });
      channels.set(m.topic, await writer.registerChannel({ topic: m.topic, schemaId, messageEncoding: "cdr", metadata: new Map() }));
      if (!writers.has(m.schema)) writers.set(m.schema, new MessageWriter(parse(SCHEMAS[m.schema], { ros2: true })));
    }
    m.bytes = writers.get(m.schema).writeMessage(m.value);
    await writer.addMessage({ channelId: channels.get(m.topic), sequence: 0, logTime: m.t, publishTime: m.t, data: m.bytes });
  }
  await writer.end();
  await handle.close();
}

async function write(dir) {
  await zstd.isLoaded;
  await lz4Decompress.isLoaded;
  const all = messages();
  for (const c of ["lz4", "zstd", "plain"]) await writeOne(`${dir}/foxglove_${c}.mcap`, c, all);
  const expected = all.map((m) => ({
    topic: m.topic,
    schema: m.schema,
    log_time: m.t.toString(),
    cdr_base64: b64(m.bytes),
    data_base64: m.value.data ? b64(m.value.data) : undefined,
    value: jsonify({ ...m.value, data: undefined }),
  }));
  await writeFile(`${dir}/foxglove_expected.json`, JSON.stringify({ files: ["lz4", "zstd", "plain"], messages: expected }, null, 1));
}

const [command, ...args] = process.argv.slice(2);
try {
  if (command === "dump" && args.length === 2) await dump(args[0], args[1]);
  else if (command === "write" && args.length === 1) await write(args[0]);
  else throw new Error("usage: foxglove_reference.mjs dump FILE.mcap OUT.json | write DIR");
} catch (e) {
  console.error(`foxglove_reference: ${e.stack ?? e}`);
  process.exit(1);
}
