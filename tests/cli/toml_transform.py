"""Mirror (x → nx−1−x) or pad (grow the domain by P voxels on every side of x and z) a 2D/3D
scenario, writing TOML: used by the end-to-end behaviour tests to check that the paper's
behaviours do not depend on orientation or on the exact domain size."""
import sys
import tomllib


def emit(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return '"' + value + '"'
    if isinstance(value, list):
        return "[" + ", ".join(emit(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {emit(v)}" for k, v in value.items()) + " }"
    raise TypeError(value)


def write(doc):
    out = []
    for k, v in doc.items():
        if not isinstance(v, (dict, list)) or (isinstance(v, list) and v and not isinstance(v[0], dict)):
            out.append(f"{k} = {emit(v)}")
    for k, v in doc.items():
        if isinstance(v, dict):
            out.append(f"[{k}]")
            for kk, vv in v.items():
                if isinstance(vv, list) and vv and isinstance(vv[0], dict):
                    continue
                out.append(f"{kk} = {emit(vv)}")
            for kk, vv in v.items():
                if isinstance(vv, list) and vv and isinstance(vv[0], dict):
                    for item in vv:
                        out.append(f"[[{k}.{kk}]]")
                        out.extend(f"{a} = {emit(b)}" for a, b in item.items())
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                out.append(f"[[{k}]]")
                out.extend(f"{a} = {emit(b)}" for a, b in item.items())
    return "\n".join(out) + "\n"


def points(doc):
    """Yields (container, key, is_box_or_list) for every position in voxel units."""
    rock = doc.get("rock", {})
    for s in rock.get("sphere", []):
        yield s, "center"
    for p in rock.get("plane", []):
        yield p, "point"
    for c in rock.get("channel", []):
        for i in range(len(c["points"])):
            yield c["points"], i
    for s in doc.get("source", []) + doc.get("sink", []):
        if "at" in s:
            yield s, "at"
        else:
            yield s["box"], 0
            yield s["box"], 1


def main():
    mode, arg, src, dst = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    doc = tomllib.load(open(src, "rb"))
    nx = doc["domain"]["size"][0]
    if mode == "mirror":
        for cont, key in points(doc):
            p = cont[key]
            cont[key] = [type(p[0])(nx - 1 - p[0])] + p[1:]
        for p in doc.get("rock", {}).get("plane", []):
            p["normal"][0] = -p["normal"][0]
        for s in doc.get("sink", []) + doc.get("source", []):
            if "box" in s:
                a, b = s["box"]
                s["box"] = [[min(a[0], b[0])] + a[1:], [max(a[0], b[0])] + b[1:]]
        doc["name"] = doc["name"] + "_mirror"
    elif mode == "pad":
        size = doc["domain"]["size"]
        doc["domain"]["size"] = [size[0] + 2 * arg, size[1], size[2] + 2 * arg]
        for cont, key in points(doc):
            p = cont[key]
            cont[key] = [p[0] + arg, p[1], p[2] + arg]
        doc["name"] = doc["name"] + "_pad"
    else:
        raise SystemExit("mode must be mirror or pad")
    doc.setdefault("output", {})["images"] = False
    doc["output"]["mesh"] = False
    doc.get("stage2", {}).pop("snapshots", None)  # pictures of the state: none without images
    open(dst, "w").write(write(doc))


main()
