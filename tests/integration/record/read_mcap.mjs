// SPDX-License-Identifier: Apache-2.0
// Opens a coxswain recording with @mcap/core (indexed and streaming readers, CRCs validated),
// compiles every jsonschema schema with Ajv (JSON Schema 2020-12), validates every JSON message
// against its schema, checks every binary message's layout version against its schema's, and
// compares the message count of every channel with what the recorder said it wrote
// (expected.json) and with the file's own Statistics record. Exit code 0 = all good.
// Usage: node read_mcap.mjs RUN.mcap expected.json
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import Ajv2020 from "ajv/dist/2020.js";
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
  } else if (schema.encoding === "coxswain-layout") {
    if (schema.data.length === 0) fail(`${schema.name}: empty layout description`);
  } else {
    fail(`${channel.topic}: unexpected schema encoding ${schema.encoding}`);
  }
}

// Messages through the index.
const counts = new Map();
let invalid = 0;
for await (const message of reader.readMessages({ validateCrcs: true })) {
  const channel = reader.channelsById.get(message.channelId);
  counts.set(channel.topic, (counts.get(channel.topic) ?? 0) + 1);
  const validate = validators.get(message.channelId);
  if (validate) {
    const value = JSON.parse(decoder.decode(message.data));
    if (!validate(value)) {
      if (invalid++ < 5) fail(`${channel.topic}: ${ajv.errorsText(validate.errors)}`);
    }
  } else {
    // The version byte is the one the channel's own schema text names ("u8 version=N").
    const schema = reader.schemasById.get(channel.schemaId);
    const named = /u8 version=(\d+)/.exec(decoder.decode(schema.data));
    if (!named || message.data[0] !== Number(named[1])) {
      fail(`${channel.topic}: binary layout version ${message.data[0]}, schema says ${named?.[1]}`);
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

// Counts: file vs. recorder vs. Statistics.
let total = 0;
for (const [topic, want] of Object.entries(expected.written)) {
  const got = counts.get(topic) ?? 0;
  total += got;
  if (got !== want) fail(`${topic}: ${got} messages in the file, the recorder wrote ${want}`);
  if (want === 0 && expected.must_have.includes(topic)) fail(`${topic}: no messages`);
}
for (const topic of counts.keys()) {
  if (!(topic in expected.written)) fail(`${topic}: unexpected channel`);
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
            `${validators.size} JSON channels validated, ${reader.chunkIndexes.length} chunks`);
for (const [topic, n] of [...counts.entries()].sort()) console.log(`  ${topic} ${n}`);
if (problems.length > 0) {
  for (const p of problems) console.error(`FAIL: ${p}`);
  process.exit(1);
}
console.log("OK");
