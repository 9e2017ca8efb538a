// Reads an MCAP file with McapIndexedReader, the TypeScript reader of Foxglove and Lichtblick,
// and prints one JSON object: the channels, each topic's message count, first and last log time,
// a message read by seeking into the middle of the file, and, for channels whose schema is one
// of Foxglove's well-known ones, how many of their messages break Foxglove's own JSON schema.
//
//   node read_mcap.mjs FILE.mcap
import { open } from "node:fs/promises";
import { createRequire } from "node:module";

import { McapIndexedReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";

const require = createRequire(import.meta.url);
const Ajv = require("ajv");
const foxgloveSchemas = require("@foxglove/schemas/jsonschema");

class FileReadable {
  constructor(handle, size) {
    this.handle = handle;
    this.fileSize = size;
  }
  async size() {
    return BigInt(this.fileSize);
  }
  async read(offset, length) {
    const buffer = new Uint8Array(Number(length));
    await this.handle.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  }
}

function wellKnownValidator(ajv, schemaName) {
  if (!schemaName.startsWith("foxglove.")) {
    return undefined;
  }
  const schema = foxgloveSchemas[schemaName.slice("foxglove.".length)];
  if (schema === undefined) {
    throw new Error(`${schemaName} is not one of Foxglove's well-known schemas`);
  }
  return ajv.compile(schema);
}

async function main() {
  const path = process.argv[2];
  const handle = await open(path, "r");
  const { size } = await handle.stat();
  const reader = await McapIndexedReader.Initialize({
    readable: new FileReadable(handle, size),
    decompressHandlers: await loadDecompressHandlers(),
  });
  const ajv = new Ajv({ strict: false, allErrors: false });
  const decoder = new TextDecoder();
  const channels = {};
  const validators = new Map();
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    channels[channel.topic] = {
      schema: schema?.name ?? null,
      schemaEncoding: schema?.encoding ?? null,
      messageEncoding: channel.messageEncoding,
    };
    validators.set(id, wellKnownValidator(ajv, schema?.name ?? ""));
  }
  const topics = {};
  for await (const message of reader.readMessages()) {
    const topic = reader.channelsById.get(message.channelId).topic;
    const entry = (topics[topic] ??= { count: 0, first: null, last: null, invalid: 0, error: null });
    entry.count += 1;
    entry.first ??= message.logTime.toString();
    entry.last = message.logTime.toString();
    const validate = validators.get(message.channelId);
    if (validate !== undefined && !validate(JSON.parse(decoder.decode(message.data)))) {
      entry.invalid += 1;
      entry.error ??= ajv.errorsText(validate.errors);
    }
  }
  // seeking: the messages of one topic from the middle of the recording on
  const start = reader.statistics.messageStartTime;
  const end = reader.statistics.messageEndTime;
  const middle = start + (end - start) / 2n;
  let seeked = null;
  for await (const message of reader.readMessages({ startTime: middle, topics: ["/interbot/tick"] })) {
    seeked = { logTime: message.logTime.toString(), tick: JSON.parse(decoder.decode(message.data)).tick };
    break;
  }
  await handle.close();
  const messageIndexes = reader.chunkIndexes.every((chunk) => chunk.messageIndexOffsets.size > 0);
  console.log(JSON.stringify({
    chunks: reader.chunkIndexes.length,
    messageIndexes,
    messageCount: reader.statistics.messageCount.toString(),
    start: start.toString(),
    end: end.toString(),
    middle: middle.toString(),
    channels,
    topics,
    seeked,
  }));
}

main().catch((error) => {
  console.error(`read_mcap.mjs: ${error.stack ?? error}`);
  process.exit(1);
});
