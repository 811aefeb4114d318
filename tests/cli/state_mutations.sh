# `cavesim report` cannot be crashed by the state file: 300 random mutations of state.cavesim, with
# the file's own trailing checksum and the run's records (report.json, scenario.toml) fixed up so
# that the damage reaches the decoder, each give exit 0 or 2, never a signal or another code.
. "$(dirname "$0")/lib.sh"
small_scenario > s.toml
expect_exit 0 "a run to mutate" -- "$CAVESIM" run s.toml --out r -q
python3 - "$CAVESIM" r <<'PY'
import json, os, random, shutil, subprocess, sys

cavesim, run = sys.argv[1], sys.argv[2]
original = open(os.path.join(run, "state.cavesim"), "rb").read()
report = json.load(open(os.path.join(run, "report.json")))
scenario = [l for l in open(os.path.join(run, "scenario.toml")) if not l.startswith("# state.cavesim:")]

def fnv(b):
    h = 0xcbf29ce484222325
    for x in b:
        h = ((h ^ x) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return h

def mutate(b, rng):
    b = bytearray(b)
    kind = rng.randrange(6)
    body = len(b) - 8
    if kind == 0:    # flip bits in a few bytes
        for _ in range(rng.randint(1, 4)):
            b[rng.randrange(body)] ^= 1 << rng.randrange(8)
    elif kind == 1:  # a header field or chunk length set to an extreme value
        at = rng.randrange(0, min(body - 4, 200))
        b[at:at + 4] = rng.choice([b"\xff\xff\xff\xff", b"\0\0\0\0", b"\0\0\0\x80", b"\x01\0\0\0"])
    elif kind == 2:  # cut the file
        b = b[:rng.randrange(len(b))] + b"\0" * 8
    elif kind == 3:  # insert bytes
        at = rng.randrange(body)
        b[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 16)))
    elif kind == 4:  # delete bytes
        at = rng.randrange(body)
        del b[at:at + rng.randint(1, 16)]
    else:            # a random byte anywhere in the first 120 (the headers)
        b[rng.randrange(min(120, body))] = rng.randrange(256)
    if len(b) >= 8:  # the file's own checksum fixed up, so the damage reaches the decoder
        b[-8:] = fnv(b[:-8]).to_bytes(8, "little")
    return bytes(b)

rng = random.Random(18)
mutations = [mutate(original, rng) for _ in range(300)]  # fixed before any run: the same 300 every time

def check(job):  # job: (worker folder, mutation number)
    folder, n = job
    data = mutations[n]
    open(os.path.join(folder, "state.cavesim"), "wb").write(data)
    record = {"bytes": len(data), "fnv1a64": "%016x" % fnv(data), "grid": report["files"]["state.cavesim"]["grid"],
              "voxel_size_m": report["files"]["state.cavesim"]["voxel_size_m"]}
    r = dict(report); r["files"] = dict(report["files"]); r["files"]["state.cavesim"] = record
    json.dump(r, open(os.path.join(folder, "report.json"), "w"))
    open(os.path.join(folder, "scenario.toml"), "w").writelines(scenario + ["# state.cavesim: " + json.dumps(record) + "\n"])
    p = subprocess.run([cavesim, "report", folder], capture_output=True, text=True, timeout=60)
    return n, p.returncode, p.stderr[-300:]

# Two workers, each on its own copy of the run folder (the machine's two cores).
import concurrent.futures
folders = []
for w in range(2):
    folders.append(run + "_w%d" % w)
    shutil.rmtree(folders[-1], ignore_errors=True)
    shutil.copytree(run, folders[-1])
codes = {}
bad = []
with concurrent.futures.ThreadPoolExecutor(2) as pool:
    results = list(pool.map(lambda w: [check((folders[w], n)) for n in range(w, 300, 2)], range(2)))
for part in results:
    for n, code, err in part:
        codes[code] = codes.get(code, 0) + 1
        if code not in (0, 2):
            bad.append((n, code, err))
print("exit codes of 300 mutated state files:", codes)
for b in bad[:5]:
    print("FAIL: mutation %d: exit %d: %s" % b)
sys.exit(1 if bad else 0)
PY
[ $? -eq 0 ] && pass "300 mutated state files: exit 0 or 2 only" || fail "a mutated state file gave another exit"
finish
