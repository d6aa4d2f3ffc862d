#!/usr/bin/env python3
"""Writes damaged copies of a checkpoint whose envelope is still valid (length and CRC-32 right):
only the driver's state (src/scenario/run.cpp, putState) is changed, the part the envelope's and
the solver's checks do not see. Usage: damage_driver_state.py CHECKPOINT FOLDER"""
import json
import struct
import sys
import zlib

source, folder = sys.argv[1], sys.argv[2]
data = open(source, 'rb').read()
head, payload = data[:32], data[44:]   # envelope: 32 bytes, u64 payload length, u32 CRC-32
# The solver's part (Solver::writeCheckpoint): 80 bytes of scalars, then lists of one value per
# cell (u64 count, doubles), then its energy ledger (3 doubles, then the folded and the boundary
# mass of up to 8 materials: 19 doubles), the body's offset and the controller's last uncut step
# (1 double each).
cells = struct.unpack_from('<Q', payload, 8)[0]
at = 80
while struct.unpack_from('<Q', payload, at)[0] == cells:
    at += 8 + 8 * cells
at += 8 * (19 + 2)
state = payload[at:]
# The driver state starts with its scalars by name: a u64 length and a JSON object.
n = struct.unpack_from('<Q', state, 0)[0]
scalars = json.loads(state[8:8 + n])
assert 'next_profile' in scalars and 'target_z_m' in scalars, 'the driver state starts with its named scalars'
kinds = 8 + n               # the impulse by kind (3 values) follows the scalars
near = kinds + 8 + 8 * 3    # then the impulse by kind within each of 3 depths of the target (9 values)
table = near + 8 + 8 * 9    # then the history table: its row count as a one-value list


def write(name, damaged):
    p = payload[:at] + damaged
    with open(f'{folder}/{name}.bin', 'wb') as f:
        f.write(head + struct.pack('<QI', len(p), zlib.crc32(p)) + p)


def scalars_with(**changes):
    """The state with some named scalars replaced (text: written as given, so it may be invalid JSON)."""
    d = dict(scalars)
    d.update(changes)
    text = ', '.join(f'"{k}": {v if isinstance(v, str) else json.dumps(v)}' for k, v in d.items())
    text = ('{' + text + '}').encode()
    return struct.pack('<Q', len(text)) + text + state[8 + n:]


write('nan-index', scalars_with(next_profile='NaN'))             # not JSON at all
write('negative-index', scalars_with(next_profile=-1))           # a count that is no count
write('missing-scalar', struct.pack('<Q', 2) + b'{}' + state[8 + n:])
write('short-kinds', state[:kinds] + struct.pack('<Qd', 1, 0.0) + state[near:])
write('short-near', state[:near] + struct.pack('<Qd', 1, 0.0) + state[table:])
write('empty-row-count', state[:table] + struct.pack('<Q', 0) + state[table + 16:])
negative = bytearray(state)
struct.pack_into('<d', negative, table + 8, -1.0)
write('negative-row-count', bytes(negative))
write('huge-list', state[:kinds] + struct.pack('<Q', 1 << 32) + state[kinds + 8:])   # 32 GiB claimed
