// SPDX-License-Identifier: Apache-2.0
// Opens a coxswain recording with @mcap/core (indexed and streaming readers, CRCs validated),
// compiles every jsonschema schema with Ajv (JSON Schema 2020-12) and validates every JSON message
// against it, decodes every protobuf message with protobufjs from the FileDescriptorSet in its
// channel's schema record (nothing of ours: the descriptors the file carries), checks every log
// time is a UTC wall-clock time near the recording's start, and compares the message count of
// every channel with what the recorder said it wrote (expected.json) and with the file's own
// Statistics record. Every channel must be one of the two: nothing Foxglove cannot decode.
// Exit code 0 = all good.
// Every foxglove.* JSON message is also validated against Foxglove's own published JSON Schema
// (@foxglove/schemas), so our schema text cannot drift from theirs unnoticed.
// Usage: node read_mcap.mjs RUN.mcap expected.json
//   expected.json: {"written": {topic: count} (optional), "must_have": [topic, ...],
//                   "layout": "path/to/foxglove-layout.json" (optional: every topic the layout
//                   names must be a channel of the file)}
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import Ajv2020 from "ajv/dist/2020.js";
import * as foxgloveSchemas from "@foxglove/schemas/jsonschema.js";
import protobuf from "protobufjs";
import descriptor from "protobufjs/ext/descriptor.js";
import { open, readFile } from "node:fs/promises";

const [file, expectedFile] = process.argv.slice(2);
const expected = JSON.parse(await readFile(expectedFile, "utf8"));
const problems = [];
const fail = (what) => problems.push(what);

const decompressHandlers = await loadDecompressHandlers();
const handle = await open(file, "r");
const { size } = await handle.stat();
const readable = {
  size: async () => BigInt(size),
  read: async (offset, length) => {
    const buffer = new Uint8Array(Number(length));
    await handle.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

// Schemas: every jsonschema one must compile (Ajv checks it against the meta-schema).
const ajv = new Ajv2020({ strict: false, allErrors: true });
const validators = new Map(); // channel id -> validate function
const official = new Map(); // channel id -> validate function of Foxglove's published schema
const protoTypes = new Map(); // channel id -> protobufjs Type
const decoder = new TextDecoder();
for (const [id, channel] of reader.channelsById) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (!schema) {
    fail(`${channel.topic}: no schema`);
    continue;
  }
  if (schema.encoding === "jsonschema") {
    try {
      const parsed = JSON.parse(decoder.decode(schema.data));
      if (!ajv.validateSchema(parsed)) fail(`${schema.name}: ${ajv.errorsText(ajv.errors)}`);
      validators.set(id, ajv.compile(parsed));
    } catch (e) {
      fail(`${schema.name}: schema does not compile: ${e.message}`);
    }
    if (channel.messageEncoding !== "json") fail(`${channel.topic}: jsonschema but not json`);
    if (schema.name.startsWith("foxglove.")) {
      const theirs = foxgloveSchemas[schema.name.slice("foxglove.".length)];
      if (!theirs) fail(`${channel.topic}: ${schema.name} is not one of Foxglove's schemas`);
      else official.set(id, ajv.compile(theirs));
    }
  } else if (schema.encoding === "protobuf") {
    try {
      const set = descriptor.FileDescriptorSet.decode(schema.data);
      const root = protobuf.Root.fromDescriptor(set);
      protoTypes.set(id, root.lookupType(schema.name));
    } catch (e) {
      fail(`${schema.name}: FileDescriptorSet does not load: ${e.message}`);
    }
    if (channel.messageEncoding !== "protobuf") fail(`${channel.topic}: protobuf schema, not message`);
  } else {
    fail(`${channel.topic}: unexpected schema encoding ${schema.encoding}`);
  }
}

// Log times: UTC nanoseconds, from the recording's start (metadata) to no later than now.
const starts = [];
for await (const m of reader.readMetadata({ name: "coxswain" })) starts.push(m);
const utcStart = starts.length === 1 ? BigInt(starts[0].metadata.get("utc_ns_at_start") ?? "0") : 0n;
if (utcStart < 1_577_836_800_000_000_000n) fail(`utc_ns_at_start ${utcStart} is not after 2020`);
const latest = BigInt(Date.now()) * 1_000_000n + 60_000_000_000n;
let badTimes = 0;

// Messages through the index.
const counts = new Map();
let invalid = 0;
let undecodable = 0;
const lastTick = { index: -1n };
for await (const message of reader.readMessages({ validateCrcs: true })) {
  const channel = reader.channelsById.get(message.channelId);
  counts.set(channel.topic, (counts.get(channel.topic) ?? 0) + 1);
  if ((message.logTime < utcStart - 1_000_000_000n || message.logTime > latest) && badTimes++ < 5) {
    fail(`${channel.topic}: log time ${message.logTime} is not a wall-clock time of this run`);
  }
  const validate = validators.get(message.channelId);
  const type = protoTypes.get(message.channelId);
  if (validate) {
    const value = JSON.parse(decoder.decode(message.data));
    if (!validate(value)) {
      if (invalid++ < 5) fail(`${channel.topic}: ${ajv.errorsText(validate.errors)}`);
    }
    const theirs = official.get(message.channelId);
    if (theirs && !theirs(value)) {
      if (invalid++ < 5) fail(`${channel.topic} (Foxglove's schema): ${ajv.errorsText(theirs.errors)}`);
    }
    checkJson(channel.topic, value);
  } else if (type) {
    let value;
    try {
      value = type.toObject(type.decode(message.data), { longs: String, defaults: true });
    } catch (e) {
      if (undecodable++ < 5) fail(`${channel.topic}: protobuf message does not decode: ${e.message}`);
      continue;
    }
    checkDecoded(channel.topic, value);
  } else {
    if (undecodable++ < 5) fail(`${channel.topic}: no decoder for this channel`);
  }
}

// The map: a GeoJSON FeatureCollection whose positions are on the globe.
function checkJson(topic, value) {
  if (topic !== "/map/geojson") return;
  let collection;
  try {
    collection = JSON.parse(value.geojson);
  } catch (e) {
    if (invalid++ < 5) fail(`/map/geojson: not JSON: ${e.message}`);
    return;
  }
  if (collection.type !== "FeatureCollection" || !Array.isArray(collection.features)) {
    if (invalid++ < 5) fail("/map/geojson: not a FeatureCollection");
    return;
  }
  const positions = (g) => (g.type === "Point" ? [g.coordinates] : g.coordinates.flat());
  for (const f of collection.features) {
    for (const [lon, lat] of positions(f.geometry)) {
      if (!(Math.abs(lat) <= 90 && Math.abs(lon) <= 180) && invalid++ < 5) {
        fail(`/map/geojson: ${f.properties?.name}: ${lon}, ${lat} is not a position`);
      }
    }
  }
}

// A few facts a decoder that read the fields wrongly would miss.
function checkDecoded(topic, value) {
  if (topic === "/tick") {
    const index = BigInt(value.tick_index);
    if (index <= lastTick.index) fail(`/tick: tick_index ${index} after ${lastTick.index}`);
    lastTick.index = index;
    if (value.health.length !== 5) fail(`/tick: ${value.health.length} health samples, not 5`);
  } else if (topic === "/lidar") {
    for (const column of ["bearing_deg", "range_m", "quality", "offset_us"]) {
      if (value[column].length !== value.point_count) {
        if (invalid++ < 5) fail(`/lidar: ${column} holds ${value[column].length} of ${value.point_count}`);
      }
    }
    if (value.bearing_deg.some((b) => !(Math.abs(b) <= 360))) fail("/lidar: a bearing out of range");
  } else if (topic === "/gnss") {
    if (value.fix_ok && !(Math.abs(value.lat_deg) <= 90 && Math.abs(value.lon_deg) <= 180)) {
      if (invalid++ < 5) fail(`/gnss: ${value.lat_deg}, ${value.lon_deg} is not a position`);
    }
  } else if (topic.startsWith("/raw/")) {
    if (!(value.data instanceof Uint8Array) || value.data.length === 0) {
      if (invalid++ < 5) fail(`${topic}: no bytes`);
    }
  }
}

// The same file through the streaming reader (data section, no index).
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(new Uint8Array(await readFile(file)));
let streamed = 0;
let sawDataEnd = false;
for (let record; (record = stream.nextRecord()); ) {
  if (record.type === "Message") streamed++;
  if (record.type === "DataEnd") sawDataEnd = true;
}
if (!stream.done()) fail("stream reader did not reach the end of the file");
if (!sawDataEnd) fail("no DataEnd record");

// Counts: file vs. recorder (when expected.json has its counters) vs. Statistics.
let total = 0;
if (expected.written) {
  for (const [topic, want] of Object.entries(expected.written)) {
    const got = counts.get(topic) ?? 0;
    total += got;
    if (got !== want) fail(`${topic}: ${got} messages in the file, the recorder wrote ${want}`);
  }
  for (const topic of counts.keys()) {
    if (!(topic in expected.written)) fail(`${topic}: unexpected channel`);
  }
} else {
  for (const n of counts.values()) total += n;
}
for (const topic of expected.must_have) {
  if (!counts.get(topic)) fail(`${topic}: no messages`);
}
if (expected.layout) {
  const channels = new Set([...reader.channelsById.values()].map((c) => c.topic));
  const layout = JSON.parse(await readFile(expected.layout, "utf8"));
  const named = layoutTopics(layout);
  if (named.size === 0) fail(`${expected.layout}: names no topic`);
  for (const topic of named) {
    if (!channels.has(topic)) fail(`${expected.layout} names ${topic}, not a channel of the file`);
  }
  // A message path into a protobuf channel must name fields of its type.
  const typeOf = new Map();
  for (const [id, type] of protoTypes) typeOf.set(reader.channelsById.get(id).topic, type);
  for (const path of layoutPaths(layout)) {
    const [topic, ...fields] = path.replace(/\[[^\]]*\]/g, "").split(".");
    let type = typeOf.get(topic);
    for (const name of fields) {
      if (!type) break;
      const field = type.fields[name];
      if (!field) {
        fail(`${expected.layout}: ${path}: ${type.name} has no field ${name}`);
        break;
      }
      type = field.resolve().resolvedType instanceof protobuf.Type ? field.resolvedType : null;
    }
  }
  console.log(`${expected.layout}: ${named.size} topics, all in the file`);
}

// Every topic string a Foxglove layout holds: the keys of the per-topic settings of a 3D or Map
// panel, the topic of an Image, Map or Log panel, and every message path ("/tick.command.x").
function layoutStrings(layout) {
  const topicKeyed = ["topics", "topicColors", "annotations"];
  const topicValued = ["value", "path", "topic", "imageTopic", "topicPath", "topicToRender",
                       "followTopic"];
  const found = [];
  const visit = (node, key) => {
    if (Array.isArray(node)) {
      for (const v of node) visit(v, key);
    } else if (node && typeof node === "object") {
      for (const [k, v] of Object.entries(node)) {
        if (topicKeyed.includes(k) && v && typeof v === "object" && !Array.isArray(v)) {
          for (const t of Object.keys(v)) if (t.startsWith("/")) found.push(t);
        }
        visit(v, k);
      }
    } else if (typeof node === "string" && node.startsWith("/") && topicValued.includes(key)) {
      found.push(node);
    }
  };
  visit(layout.configById ?? layout, "");
  return found;
}
function layoutTopics(layout) {
  return new Set(layoutStrings(layout).map((s) => s.split(/[.{[]/)[0]));
}
function layoutPaths(layout) {
  return layoutStrings(layout).filter((s) => s.includes("."));
}

const stats = reader.statistics;
if (!stats) fail("no Statistics record");
else {
  if (Number(stats.messageCount) !== total) fail(`Statistics says ${stats.messageCount}, read ${total}`);
  for (const [id, n] of stats.channelMessageCounts) {
    const topic = reader.channelsById.get(id).topic;
    if (Number(n) !== (counts.get(topic) ?? 0)) fail(`Statistics count of ${topic} is ${n}`);
  }
}
if (streamed !== total) fail(`stream reader saw ${streamed} messages, indexed reader ${total}`);
const meta = [];
for await (const m of reader.readMetadata({ name: "config" })) meta.push(m);
if (meta.length !== 1 || !meta[0].metadata.get("yaml")) fail("config metadata missing");

await handle.close();
console.log(`${file}: ${reader.channelsById.size} channels, ${total} messages, ` +
            `${validators.size} JSON and ${protoTypes.size} protobuf channels decoded, ` +
            `${reader.chunkIndexes.length} chunks`);
for (const [topic, n] of [...counts.entries()].sort()) console.log(`  ${topic} ${n}`);
if (problems.length > 0) {
  for (const p of problems) console.error(`FAIL: ${p}`);
  process.exit(1);
}
console.log("OK");
