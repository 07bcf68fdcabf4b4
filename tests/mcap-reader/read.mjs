// Reads an MCAP file with @mcap/core, the format's reference TypeScript reader, twice: from start to end
// (McapStreamReader, every chunk's CRC checked) and through the summary (McapIndexedReader, the summary's
// CRC checked, messages found through chunk and message indexes). Prints one JSON object: the summary,
// what each pass found, every message decoded as JSON, and where messages depart from their channel's
// JSON schema. Exits 1 with the reader's error otherwise.
// Usage: node read.mjs FILE.mcap
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { readFile } from "node:fs/promises";
import { crc32 } from "node:zlib";

// Where `value` departs from the JSON Schema `schema` (the subset Foxglove's schemas use: object
// properties and required fields, arrays, number, integer, string, boolean, oneOf consts): a field
// missing or not declared, a value of another type, an enum value not listed.
function departures(value, schema, path, out) {
  if (schema.oneOf) {
    if (!schema.oneOf.some((o) => o.const === value)) out.push(`${path}: ${JSON.stringify(value)} is none of the schema's values`);
    return out;
  }
  const type = schema.type;
  const ok = {
    object: () => value !== null && typeof value === "object" && !Array.isArray(value),
    array: () => Array.isArray(value),
    number: () => typeof value === "number" && Number.isFinite(value),
    integer: () => Number.isInteger(value),
    string: () => typeof value === "string",
    boolean: () => typeof value === "boolean",
  }[type];
  if (!ok || !ok()) return out.push(`${path}: ${JSON.stringify(value)?.slice(0, 40)} is not of type ${type}`), out;
  if (type === "object") {
    for (const k of schema.required ?? []) if (!(k in value)) out.push(`${path}.${k}: required, missing`);
    for (const [k, v] of Object.entries(value)) {
      if (!schema.properties?.[k]) out.push(`${path}.${k}: not in the schema`);
      else departures(v, schema.properties[k], `${path}.${k}`, out);
    }
  }
  if (type === "array") value.forEach((v, i) => departures(v, schema.items, `${path}[${i}]`, out));
  return out;
}

// Where a schema uses what a viewer cannot turn into message fields: every field needs a type among
// object (with properties), array (with typed items), number, integer, string, boolean, or a oneOf of
// numeric consts (an enum), and the root is an object.
function schemaProblems(schema, path, out) {
  if (schema.oneOf) {
    if (!schema.oneOf.every((o) => typeof o.const === "number")) out.push(`${path}: oneOf without numeric consts`);
    return out;
  }
  if (!["object", "array", "number", "integer", "string", "boolean"].includes(schema.type)) out.push(`${path}: type ${JSON.stringify(schema.type)}`);
  if (schema.type === "object") {
    if (typeof schema.properties !== "object") out.push(`${path}: an object without properties`);
    for (const [k, v] of Object.entries(schema.properties ?? {})) schemaProblems(v, `${path}.${k}`, out);
  }
  if (schema.type === "array") {
    if (!schema.items) out.push(`${path}: an array without items`);
    else schemaProblems(schema.items, `${path}[]`, out);
  }
  return out;
}

const file = process.argv[2];
if (!file) {
  console.error("usage: node read.mjs FILE.mcap");
  process.exit(2);
}
const bytes = new Uint8Array(await readFile(file));
const str = (v) => (typeof v === "bigint" ? v.toString() : v);
const decoder = new TextDecoder();

// Pass 1: the stream, record by record.
const stream = new McapStreamReader({ validateCrcs: true });
stream.append(bytes);
const streamed = { records: {}, messages: 0, dataEnd: null };
let dataEndAt = 0;
for (let record; (record = stream.nextRecord()); ) {
  streamed.records[record.type] = (streamed.records[record.type] ?? 0) + 1;
  if (record.type === "Message") streamed.messages++;
  if (record.type === "DataEnd") streamed.dataEnd = record.dataSectionCrc;
}
if (!stream.done()) throw new Error("the stream ended before the footer's magic");
// The data section's CRC: every byte before the Data End record (magic and header included).
const footerStart = bytes.length - 8 - (1 + 8 + 20);
const summaryStart = Number(new DataView(bytes.buffer).getBigUint64(footerStart + 9, true));
dataEndAt = (summaryStart || footerStart) - 13;
streamed.dataSectionCrcMatches = streamed.dataEnd === crc32(bytes.subarray(0, dataEndAt));

// Pass 2: through the summary.
const reader = await McapIndexedReader.Initialize({
  readable: {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  },
});
const topicOf = new Map([...reader.channelsById].map(([id, c]) => [id, c.topic]));
const stats = reader.statistics;
const out = {
  header: reader.header,
  schemas: [...reader.schemasById.values()].map((s) => {
    const schema = JSON.parse(decoder.decode(s.data));
    const problems = schema.type === "object" ? schemaProblems(schema, s.name, []) : [`${s.name}: the root is not an object`];
    return { id: s.id, name: s.name, encoding: s.encoding, schema, problems };
  }),
  channels: [...reader.channelsById.values()].map((c) => ({ id: c.id, topic: c.topic, schemaId: c.schemaId, messageEncoding: c.messageEncoding })),
  statistics: stats && {
    messageCount: str(stats.messageCount), schemaCount: stats.schemaCount, channelCount: stats.channelCount,
    chunkCount: stats.chunkCount, messageStartTime: str(stats.messageStartTime), messageEndTime: str(stats.messageEndTime),
    channelMessageCounts: Object.fromEntries([...stats.channelMessageCounts].map(([id, n]) => [topicOf.get(id), str(n)])),
  },
  chunkIndexes: reader.chunkIndexes.length,
  summaryOffsets: [...reader.summaryOffsetsByOpcode.keys()],
  stream: streamed,
  messages: [],
};
const schemaOf = new Map([...reader.channelsById].map(([id, c]) => [id, JSON.parse(decoder.decode(reader.schemasById.get(c.schemaId).data))]));
out.schemaDepartures = [];
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const data = JSON.parse(decoder.decode(m.data));
  out.schemaDepartures.push(...departures(data, schemaOf.get(m.channelId), topicOf.get(m.channelId), []).slice(0, 5));
  out.messages.push({
    topic: topicOf.get(m.channelId), sequence: m.sequence, logTime: str(m.logTime), publishTime: str(m.publishTime),
    data,
  });
}
// A seek: the messages of the last second only, found through the indexes.
const end = stats ? stats.messageEndTime : 0n;
let late = 0;
for await (const m of reader.readMessages({ startTime: end > 1_000_000_000n ? end - 1_000_000_000n : 0n })) late += m.logTime >= 0n ? 1 : 0;
out.lastSecondMessages = late;
process.stdout.write(JSON.stringify(out));
