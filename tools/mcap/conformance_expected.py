#!/usr/bin/env python3
"""The messages every MCAP conformance file holds, from the MCAP project's own expected-output
JSON files (tests/conformance/data/*/*.json in github.com/foxglove/mcap), in a form a C++ test
reads without a JSON library:
  python3 tools/mcap/conformance_expected.py MCAP_CHECKOUT/tests/conformance/data > expected.txt
One line per file, "file <group>/<name>.mcap <message count>", then one line per message in
order, "<channel id> <topic> <log time> <publish time> <sequence> <data as hex or ->" (topics in
these files have no spaces; a schemaless channel's topic is as written)."""
import json
import pathlib
import sys

root = pathlib.Path(sys.argv[1])
for path in sorted(root.glob("*/*.json")):
    records = json.loads(path.read_text())["records"]
    topics, messages = {}, []
    for record in records:
        fields = dict(record["fields"])
        if record["type"] == "Channel":
            topics[fields["id"]] = fields["topic"]
        elif record["type"] == "Message":
            data = bytes(int(b) for b in fields["data"]).hex() or "-"
            messages.append(" ".join([fields["channel_id"], topics[fields["channel_id"]],
                                      fields["log_time"], fields["publish_time"],
                                      fields["sequence"], data]))
    print(f"file {path.parent.name}/{path.stem}.mcap {len(messages)}")
    for line in messages:
        print(line)
