// ROS 2 recordings of sensor_msgs/JointState written by other people's writers, not dynid's: MCAP
// by the MCAP project's own TypeScript writer (@mcap/core, chunks compressed by @foxglove/wasm-zstd
// and lz4js), CDR by Foxglove's ROS 2 serializer (@foxglove/rosmsg2-serialization),
// rosbag2's SQLite files by SQLite itself (sql.js) in the tables rosbag2_storage_sqlite3 creates.
// tools/mcap/README.md says how to install the pinned packages (the npm registry; nothing of this
// runs at build or test time).
//
//   node tools/mcap/joint_states.mjs fixtures OUT_DIR      the small fixtures of
//                                                          tests/data/bags/fixtures/ros2/
//   node tools/mcap/joint_states.mjs panda LOG_DIR OUT_DIR  Gaz et al.'s real Panda log
//
// Fixtures: 200 JointState messages on /joint_states at 1 kHz, header stamps 1700000000 s + k ms,
// received (log time) 250 us after their stamp, joints named joint2, joint1, gripper in that
// order, and a std_msgs/String on /chatter every 50th message. Joint j (1-based name number;
// gripper 3) at message k: position = 0.1 j sin(0.01 k), velocity = 0.001 j cos(0.01 k),
// effort = 2 j + 0.5 k (the ROS 1 fixtures' values, tools/make_ros1_bag_fixtures.py).
//   joint_states_zstd.mcap   chunked, zstd, summary with every index and statistics (defaults)
//   joint_states_lz4.mcap    lz4 chunks of 4 KiB (several chunks), summary
//   joint_states_plain.mcap  no chunks, no summary, no index
//   joint_states.db3         rosbag2 SQLite
//   joint_states_split/      a bag directory: metadata.yaml and two .db3 files of 100 messages,
//                            whose topic ids differ (the second registers /chatter first)
//   joint_states_effort_topic.mcap  positions and velocities on /joint_states, no effort; the
//                            efforts on /joint_efforts every 2 ms, between the position stamps
//                            (effortTopicMessages says how)
// Panda: every logged sample as one message on /franka/joint_states, header stamps
// 1700000000 s + the log's time rounded to the ns, joints joint1..joint7 published in another
// order with a finger joint beside them, position and effort from the log (as
// tools/panda_log_as_ros1_bag.py): OUT_DIR/panda.mcap (zstd) and OUT_DIR/panda_db3/ (a bag
// directory split in two .db3 files).
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import * as zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";
import initSqlJs from "sql.js";
import fs from "node:fs";
import path from "node:path";

const JOINT_STATE = `std_msgs/Header header
string[] name
float64[] position
float64[] velocity
float64[] effort
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
`;
const STRING = "string data\n";
const jointState = new MessageWriter(parse(JOINT_STATE, { ros2: true }));
const string = new MessageWriter(parse(STRING, { ros2: true }));

const SECOND = 1000000000n;
const stampOf = (ns) => ({ sec: Number(ns / SECOND), nanosec: Number(ns % SECOND) });

/// The fixtures' messages: [topic, type, receive ns, CDR bytes].
function fixtureMessages() {
  const numbers = { joint2: 2, joint1: 1, gripper: 3 };
  const out = [];
  for (let k = 0; k < 200; k++) {
    const stamp = 1700000000n * SECOND + BigInt(k) * 1000000n;
    const receive = stamp + 250000n;
    const j = Object.values(numbers);
    out.push(["/joint_states", "sensor_msgs/msg/JointState", receive, jointState.writeMessage({
      header: { stamp: stampOf(stamp), frame_id: "base_link" },
      name: Object.keys(numbers),
      position: j.map((n) => 0.1 * n * Math.sin(0.01 * k)),
      velocity: j.map((n) => 0.001 * n * Math.cos(0.01 * k)),
      effort: j.map((n) => 2.0 * n + 0.5 * k),
    })]);
    if (k % 50 === 0)
      out.push(["/chatter", "std_msgs/msg/String", receive,
                string.writeMessage({ data: `message ${k}` })]);
  }
  return out;
}

/// The fixtures' motion with the efforts on their own topic: /joint_states carries position and
/// velocity only; /joint_efforts (JointState, effort only, joints in another order) every 2 ms,
/// 0.5 ms after the positions' stamps, with the same linear effort law (so that interpolation
/// at the position stamps gives the fixtures' efforts).
function effortTopicMessages() {
  const numbers = { joint2: 2, joint1: 1, gripper: 3 };
  const out = [];
  for (let k = 0; k < 200; k++) {
    const stamp = 1700000000n * SECOND + BigInt(k) * 1000000n;
    const j = Object.values(numbers);
    out.push(["/joint_states", "sensor_msgs/msg/JointState", stamp + 250000n,
      jointState.writeMessage({
        header: { stamp: stampOf(stamp), frame_id: "base_link" },
        name: Object.keys(numbers),
        position: j.map((n) => 0.1 * n * Math.sin(0.01 * k)),
        velocity: j.map((n) => 0.001 * n * Math.cos(0.01 * k)),
        effort: [],
      })]);
    if (k % 2 === 1 || k === 0) {
      const at = k === 0 ? stamp - 500000n : stamp + 500000n;  // one sample before the first
      const kk = Number(at - 1700000000n * SECOND) / 1e6;      // in position samples
      out.push(["/joint_efforts", "sensor_msgs/msg/JointState", at + 250000n,
        jointState.writeMessage({
          header: { stamp: stampOf(at), frame_id: "" },
          name: ["gripper", "joint1", "joint2"],
          position: [], velocity: [],
          effort: [3, 1, 2].map((n) => 2.0 * n + 0.5 * kk),
        })]);
    }
  }
  return out;
}

/// The Panda log's messages (see the header).
function pandaMessages(logDir) {
  const numbers = (name) =>
    fs.readFileSync(path.join(logDir, name), "utf8").split(/\s+/).filter((s) => s !== "")
      .map(Number);
  const t = numbers("exciting_traj_time.txt");
  const q = numbers("exciting_traj_positions.txt");
  const tau = numbers("exciting_traj_torques.txt");
  const n = 7, order = [6, 0, 3, 1, 5, 2, 4];  // not the robot's order
  return t.map((seconds, k) => {
    const stamp = 1700000000n * SECOND + BigInt(Math.round(seconds * 1e9));
    return ["/franka/joint_states", "sensor_msgs/msg/JointState", stamp,
      jointState.writeMessage({
        header: { stamp: stampOf(stamp), frame_id: "" },
        name: order.map((i) => `joint${i + 1}`).concat(["finger_joint1"]),
        position: order.map((i) => q[k * n + i]).concat([0.04]),
        velocity: [],
        effort: order.map((i) => tau[k * n + i]).concat([0.0]),
      })];
  });
}

const definitionOf = { "sensor_msgs/msg/JointState": JOINT_STATE, "std_msgs/msg/String": STRING };

class FileWritable {
  constructor(file) { this.fd = fs.openSync(file, "w"); this.size = 0n; }
  async write(buffer) { fs.writeSync(this.fd, buffer); this.size += BigInt(buffer.byteLength); }
  position() { return this.size; }
  close() { fs.closeSync(this.fd); }
}

async function writeMcap(file, messages, options) {
  const writable = new FileWritable(file);
  const writer = new McapWriter({ writable, ...options });
  await writer.start({ profile: "ros2", library: "@mcap/core (dynid tools/mcap/joint_states.mjs)" });
  const channels = new Map();
  let sequence = 0;
  for (const [topic, type, receive, data] of messages) {
    if (!channels.has(topic)) {
      const schemaId = await writer.registerSchema({
        name: type, encoding: "ros2msg", data: new TextEncoder().encode(definitionOf[type]) });
      channels.set(topic, await writer.registerChannel({
        topic, schemaId, messageEncoding: "cdr", metadata: new Map() }));
    }
    await writer.addMessage({ channelId: channels.get(topic), sequence: sequence++,
                              logTime: receive, publishTime: receive, data });
  }
  await writer.end();
  writable.close();
}

/// rosbag2's SQLite storage (schema version 4 of rosbag2_storage_sqlite3), topics registered in
/// `topicOrder` (ids 1, 2, ...).
async function writeDb3(file, messages, topicOrder) {
  const SQL = await initSqlJs();
  const db = new SQL.Database();
  db.run(`CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
    CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,
                          metadata TEXT NOT NULL);
    CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                        serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL,
                        type_description_hash TEXT NOT NULL);
    CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL,
                                     encoding TEXT NOT NULL,
                                     encoded_message_definition TEXT NOT NULL,
                                     type_description_hash TEXT NOT NULL);
    CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
                          timestamp INTEGER NOT NULL, data BLOB NOT NULL);
    CREATE INDEX timestamp_idx ON messages (timestamp ASC);
    INSERT INTO schema (schema_version, ros_distro) VALUES (4, 'jazzy');`);
  const ids = new Map();
  for (const topic of topicOrder) {
    const type = messages.find((m) => m[0] === topic)[1];
    db.run("INSERT INTO topics (name, type, serialization_format, offered_qos_profiles, " +
           "type_description_hash) VALUES (?, ?, 'cdr', '', '')", [topic, type]);
    ids.set(topic, db.exec("SELECT last_insert_rowid()")[0].values[0][0]);
    db.run("INSERT INTO message_definitions (topic_type, encoding, encoded_message_definition, " +
           "type_description_hash) VALUES (?, 'ros2msg', ?, '')", [type, definitionOf[type]]);
  }
  const insert = db.prepare("INSERT INTO messages (timestamp, topic_id, data) VALUES (?, ?, ?)");
  db.run("BEGIN");
  for (const [topic, , receive, data] of messages)
    insert.run([receive.toString(), ids.get(topic), data]);
  db.run("COMMIT");
  insert.free();
  fs.writeFileSync(file, db.export());
  db.close();
}

/// A rosbag2 bag directory: `parts` .db3 files and the metadata.yaml that lists them, in
/// rosbag2's layout (metadata version 9).
async function writeSplitDb3(dir, messages, parts, topicOrders) {
  fs.mkdirSync(dir, { recursive: true });
  const name = path.basename(dir);
  const per = Math.ceil(messages.length / parts);
  const files = [];
  for (let p = 0; p < parts; p++) {
    const part = messages.slice(p * per, (p + 1) * per);
    files.push(`${name}_${p}.db3`);
    await writeDb3(path.join(dir, files[p]), part,
                   topicOrders[p].filter((t) => part.some((m) => m[0] === t)));
  }
  const counts = new Map();
  for (const [topic, type] of messages) counts.set(topic, [type, (counts.get(topic)?.[1] ?? 0) + 1]);
  const first = messages[0][2], last = messages[messages.length - 1][2];
  const yaml = [
    "rosbag2_bagfile_information:", "  version: 9", "  storage_identifier: sqlite3",
    "  duration:", `    nanoseconds: ${last - first}`, "  starting_time:",
    `    nanoseconds_since_epoch: ${first}`, `  message_count: ${messages.length}`,
    "  topics_with_message_count:",
    ...[...counts].flatMap(([topic, [type, count]]) => [
      "    - topic_metadata:", `        name: ${topic}`, `        type: ${type}`,
      "        serialization_format: cdr", "        offered_qos_profiles: \"\"",
      "        type_description_hash: \"\"", `      message_count: ${count}`]),
    "  compression_format: \"\"", "  compression_mode: \"\"", "  relative_file_paths:",
    ...files.map((f) => `    - ${f}`), "  files:",
    ...files.map((f) => `    - path: ${f}`), "  custom_data: ~", "  ros_distro: jazzy", ""];
  fs.writeFileSync(path.join(dir, "metadata.yaml"), yaml.join("\n"));
}

await zstd.isLoaded;
const zstdChunk = (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 19) });
const lz4Chunk = (data) => ({ compression: "lz4", compressedData: Uint8Array.from(lz4.compress(data)) });
const [mode, ...args] = process.argv.slice(2);
if (mode === "fixtures" && args.length === 1) {
  const out = args[0], messages = fixtureMessages();
  fs.mkdirSync(out, { recursive: true });
  await writeMcap(path.join(out, "joint_states_zstd.mcap"), messages, { compressChunk: zstdChunk });
  await writeMcap(path.join(out, "joint_states_lz4.mcap"), messages,
                  { compressChunk: lz4Chunk, chunkSize: 4096 });
  await writeMcap(path.join(out, "joint_states_plain.mcap"), messages, {
    useChunks: false, useStatistics: false, useSummaryOffsets: false, useChunkIndex: false,
    useMessageIndex: false, useAttachmentIndex: false, useMetadataIndex: false,
    repeatSchemas: false, repeatChannels: false });
  await writeDb3(path.join(out, "joint_states.db3"), messages, ["/joint_states", "/chatter"]);
  await writeSplitDb3(path.join(out, "joint_states_split"), messages, 2,
                      [["/joint_states", "/chatter"], ["/chatter", "/joint_states"]]);
  await writeMcap(path.join(out, "joint_states_effort_topic.mcap"), effortTopicMessages(),
                  { compressChunk: zstdChunk });
} else if (mode === "panda" && args.length === 2) {
  const [log, out] = args, messages = pandaMessages(log);
  fs.mkdirSync(out, { recursive: true });
  await writeMcap(path.join(out, "panda.mcap"), messages, { compressChunk: zstdChunk });
  await writeSplitDb3(path.join(out, "panda_db3"), messages, 2, [[messages[0][0]], [messages[0][0]]]);
} else {
  console.error("usage: node joint_states.mjs fixtures OUT_DIR | panda LOG_DIR OUT_DIR");
  process.exit(2);
}
