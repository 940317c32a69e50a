"""Reads a juggle trajectory file (docs/recording.md, format version 2); standard library only.

    from trajectory import read_trajectory
    header, channels, rows = read_trajectory("run.traj")
    # header: {"family": ..., "config": ..., "control_dt": ..., "nq": ...}
    # channels: [(name, labels)], rows: [{"time": t, <channel>: value, ..., "qpos": [...]}]
"""
import struct


def read_trajectory(path):
    with open(path, "rb") as f:
        magic = f.readline().decode().split()
        if magic[:2] != ["juggle-trajectory", "2"]:
            raise ValueError(f"{path}: not a version-2 juggle trajectory")
        header, channels, count = {}, [], None
        while count is None:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: header has no data line")
            key, _, value = line.decode().rstrip("\n").partition(" ")
            if key == "channel":
                name, _, labels = value.partition(" ")
                channels.append((name, labels.split(",") if labels else []))
            elif key == "data":
                count = int(value)
            else:
                header[key] = value
        nq = int(header["nq"])
        width = 1 + len(channels) + nq
        body = f.read()
    if len(body) != count * width * 8:
        raise ValueError(f"{path}: truncated ({len(body)} bytes, expected {count * width * 8})")
    rows = []
    for r, values in enumerate(struct.iter_unpack(f"<{width}d", body)):
        row = {"time": values[0], "qpos": list(values[1 + len(channels):])}
        for c, (name, _) in enumerate(channels):
            row[name] = values[1 + c]
        rows.append(row)
    return header, channels, rows
