"""``replay.html``: one self-contained page (inline script and data, no server, no network) that
replays a run with a timeline scrubber: the map, the global and local costmaps, the laser, the
planned path, the robot's footprint and trajectory, AMCL's particles, the tree with each node's
status at that tick, and the blackboard.

The page's data (``<script id="run-data" type="application/json">``) is built from the tick log
and, when the run was recorded with a ``RunCapture``, its sampled scans, costmaps and particles;
``read_page_data`` reads it back (``mission replay RUN --tick N -f png`` draws a frame from it).
Big arrays travel as base64 (laser hits as int16 centimetres, costmaps as PNG images).
"""

from __future__ import annotations

import base64
import html
import io
import json
import math
from typing import Any, Sequence

import numpy as np
from PIL import Image

from navcore.maps import OccupancyGrid

MAX_SCANS = 1500           # evenly chosen when a long run captured more
MAX_LOCAL_COSTMAPS = 600
MAX_GLOBAL_COSTMAPS = 16
MAX_PARTICLE_SETS = 600
SCAN_POINTS = 240
MARGIN_M = 2.0

def _b64(a: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(a).tobytes()).decode("ascii")


def path_code(points: Sequence[Sequence[float]]) -> Any:
    """A planned path for the page: ``[x0, y0, steps]``, its first point and the others as
    base64 int16 centimetres from it (a third of the JSON list's size: a long run replans
    hundreds of times), or the list itself when it is empty or reaches beyond 327 m."""
    if len(points) == 0:
        return []
    a = np.asarray(points, dtype=float)[:, :2]
    off = np.round((a - a[0]) * 100.0)
    if not np.all(np.abs(off) <= 32767):
        return [list(map(float, q[:2])) for q in points]
    return [float(a[0, 0]), float(a[0, 1]), _b64(off.astype("<i2"))]


def path_points(code: Any) -> list[list[float]]:
    """The points of a path as ``path_code`` wrote it (or of a plain list)."""
    if len(code) == 3 and isinstance(code[2], str):
        off = np.frombuffer(base64.b64decode(code[2]), "<i2").reshape(-1, 2) / 100.0
        return (off + np.array([code[0], code[1]])).tolist()
    return [list(q) for q in code]


def _costmap_palette() -> tuple[list[int], bytes]:
    """RGB palette and alpha per costmap value: inflation blue with an alpha that grows with
    cost, inscribed (253) orange, lethal (254) magenta, free and unknown transparent."""
    rgb, alpha = [], []
    for c in range(256):
        if 0 < c < 253:
            rgb += [70, 100, 255]
            alpha.append(int(25 + 130 * c / 252.0))
        elif c == 253:
            rgb += [235, 140, 40]
            alpha.append(150)
        elif c == 254:
            rgb += [200, 30, 120]
            alpha.append(210)
        else:
            rgb += [0, 0, 0]
            alpha.append(0)
    return rgb, bytes(alpha)


_PALETTE_RGB, _PALETTE_ALPHA = _costmap_palette()


def costmap_png(costs: np.ndarray) -> str:
    """A costmap as a PNG data URI, row 0 at the bottom: the cost values are the pixels of a
    palette image (a fraction of the size of RGBA, and as fast to draw)."""
    return _palette_png(costs, _PALETTE_RGB, _PALETTE_ALPHA)


# the map's cells as palette indices 0 free, 1 unknown, 2 occupied (see _occupancy_codes)
_MAP_PALETTE = [255, 255, 255, 205, 205, 205, 30, 30, 30] + [0, 0, 0] * 253


def _palette_png(values: np.ndarray, palette: list[int], alpha: bytes | None) -> str:
    """``values`` (row 0 = lowest y) as the pixels of a palette PNG data URI. Level 3: a
    Willow Garage global costmap encodes in half the time of level 6 for a fifth more bytes."""
    img = Image.fromarray(np.ascontiguousarray(values[::-1], dtype=np.uint8), "P")
    img.putpalette(palette)
    buf = io.BytesIO()
    if alpha is None:
        img.save(buf, "PNG", compress_level=3)
    else:
        img.save(buf, "PNG", transparency=alpha, compress_level=3)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _pick(items: Sequence[Any], limit: int) -> list[Any]:
    if len(items) <= limit:
        return list(items)
    idx = np.linspace(0, len(items) - 1, limit).round().astype(int)
    return [items[i] for i in idx]


def _bounds(ticks: list[dict[str, Any]], goals: list[Any], grid: OccupancyGrid | None
            ) -> tuple[float, float, float, float]:
    pts = [t["pose"][:2] for t in ticks if "pose" in t] + [g[:2] for g in goals]
    for t in ticks:
        p = t.get("bb", {}).get("path")
        if isinstance(p, dict) and p.get("path"):
            pts += [q[:2] for q in p["path"][:: max(1, len(p["path"]) // 20)]]
    if not pts and grid is not None:
        o = grid.origin
        return o.x, o.y, o.x + grid.width * grid.resolution, o.y + grid.height * grid.resolution
    if not pts:
        return -5.0, -5.0, 5.0, 5.0
    a = np.asarray(pts, float)
    (x0, y0), (x1, y1) = a.min(axis=0) - MARGIN_M, a.max(axis=0) + MARGIN_M
    return float(x0), float(y0), float(x1), float(y1)


def _grid_crop(costs: np.ndarray, res: float, ox: float, oy: float,
               box: tuple[float, float, float, float]) -> tuple[np.ndarray, float, float] | None:
    """The part of a grid inside ``box`` (world x0, y0, x1, y1), with its new origin."""
    c0 = max(0, int(math.floor((box[0] - ox) / res)))
    r0 = max(0, int(math.floor((box[1] - oy) / res)))
    c1 = min(costs.shape[1], int(math.ceil((box[2] - ox) / res)))
    r1 = min(costs.shape[0], int(math.ceil((box[3] - oy) / res)))
    if c1 <= c0 or r1 <= r0:
        return None
    return costs[r0:r1, c0:c1], ox + c0 * res, oy + r0 * res


def page_data(header: dict[str, Any], ticks: list[dict[str, Any]],
              footer: dict[str, Any] | None, *, grid: OccupancyGrid | None = None,
              capture: Any = None, footprint: Sequence[Sequence[float]] = (),
              title: str = "") -> dict[str, Any]:
    """Everything the page shows, as one JSON-able dict."""
    nodes = header.get("nodes", [])
    kinds = _kinds(nodes)
    goals = [list(e["goal"]) for t in ticks for e in t.get("events", ()) if "goal" in e]
    box = _bounds(ticks, goals, grid)
    data: dict[str, Any] = {
        "title": title or header.get("scenario") or "run",
        "period": header.get("period"),
        "nodes": [[n[0], n[1], n[2], kinds[i]] for i, n in enumerate(nodes)],
        "footprint": [list(map(float, p)) for p in footprint],
        "box": [round(v, 3) for v in box],
        "goals": goals,
        "footer": {k: v for k, v in (footer or {}).items()
                   if k in ("outcome", "reason", "time_s", "goals_reached", "goals_total",
                            "recoveries", "collisions")},
        "ticks": [], "t": [], "pose": [], "cmd": [], "root": [],
        "status": [], "bb": [], "events": [], "paths": [],
    }
    for i, line in enumerate(ticks):
        data["ticks"].append(line["tick"])
        data["t"].append(line["t"])
        data["pose"].append(line.get("pose"))
        data["cmd"].append(line.get("cmd"))
        data["root"].append(line.get("root", ""))
        if line.get("status"):
            data["status"].append([i, line["status"]])
        bb = {k: v for k, v in line.get("bb", {}).items()}
        path = bb.pop("path", None)
        if isinstance(path, dict) and "path" in path:
            data["paths"].append([i, path_code(path["path"])])
            bb["path"] = f"<path of {len(path['path'])} points>"
        elif path is None and "path" in line.get("bb", {}):
            data["paths"].append([i, []])
            bb["path"] = None
        if bb:
            data["bb"].append([i, bb])
        if line.get("events"):
            data["events"].append([i, line["events"]])
    if grid is not None:
        crop = _grid_crop(_occupancy_codes(grid), grid.resolution, grid.origin.x, grid.origin.y,
                          box)
        if crop is not None:
            codes, cx, cy = crop
            data["map"] = {"png": _palette_png(codes, _MAP_PALETTE, None), "res": grid.resolution,
                           "ox": cx, "oy": cy, "w": codes.shape[1], "h": codes.shape[0]}
    if capture is not None:
        index = {tick: i for i, tick in enumerate(data["ticks"])}
        data["scans"] = []
        for s in _pick(capture.scans, MAX_SCANS):
            if s.tick not in index:
                continue
            cm = np.clip(np.round(s.points(SCAN_POINTS) * 100.0), -32767, 32767).astype("<i2")
            lp = s.laser_pose
            data["scans"].append([index[s.tick], [round(lp.x, 3), round(lp.y, 3),
                                                  round(lp.theta, 3)], _b64(cm)])
        for key, samples, limit in (("local", capture.local_costmaps, MAX_LOCAL_COSTMAPS),
                                    ("global", capture.global_costmaps, MAX_GLOBAL_COSTMAPS)):
            out = []
            for g in _pick(samples, limit):
                crop = _grid_crop(g.costs, g.resolution, g.origin_x, g.origin_y, box)
                if crop is None or g.tick not in index:
                    continue
                costs, cx, cy = crop
                out.append([index[g.tick], {"png": costmap_png(costs),
                                            "res": g.resolution, "ox": cx, "oy": cy,
                                            "w": costs.shape[1], "h": costs.shape[0]}])
            data[key + "_costmaps"] = out
        parts = []
        for tick, _t, p in _pick(capture.particles, MAX_PARTICLE_SETS):
            if tick in index and len(p):
                parts.append([index[tick], _b64(np.round(p[:, :2] * 100).clip(-32767, 32767)
                                                .astype("<i2"))])
        data["particles"] = parts
        if capture.has_localisation:
            data["truth"] = [[round(v, 3) for v in p] for p in capture.truth]
    return data


def _occupancy_codes(grid: OccupancyGrid) -> np.ndarray:
    d = grid.data
    codes = np.ones(d.shape, np.uint8)   # unknown
    codes[d == 0] = 0
    codes[d >= 65] = 2
    return codes


def _kinds(nodes: Sequence[Sequence[Any]]) -> list[str]:
    """Node kind per recorded ``[name, type, depth]`` row, from the registered classes."""
    from behaviors.base import node_classes
    classes = node_classes()
    out = []
    for i, (_, type_name, depth) in enumerate(nodes):
        cls = classes.get(type_name)
        if cls is not None:
            kind = {"Control": "control", "Decorator": "decorator",
                    "Condition": "condition"}.get(getattr(cls, "CATEGORY", ""), "action")
        else:  # a stock py_trees node: tell by whether the next row is its child
            has_child = i + 1 < len(nodes) and nodes[i + 1][2] > depth
            kind = "control" if has_child else "action"
        out.append(kind)
    return out


def render_page(data: dict[str, Any]) -> str:
    """The HTML of the page around ``data``."""
    blob = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return (_TEMPLATE.replace("__TITLE__", html.escape(str(data.get("title", "run"))))
            .replace("__DATA__", blob))


def write_replay(path: str, header: dict[str, Any], ticks: list[dict[str, Any]],
                 footer: dict[str, Any] | None, **kwargs: Any) -> int:
    """Write the page to ``path``; returns its size in bytes."""
    text = render_page(page_data(header, ticks, footer, **kwargs))
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return len(text.encode("utf-8"))


def read_page_data(path: str) -> dict[str, Any]:
    """The data block of a replay page written by ``write_replay``."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    start = text.find('<script id="run-data" type="application/json">')
    if start < 0:
        raise ValueError(f"{path}: not a navbt replay page (no run-data block)")
    start = text.index(">", start) + 1
    end = text.index("</script>", start)
    return json.loads(text[start:end].replace("<\\/", "</"))


_TEMPLATE = r"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>__TITLE__ - navbt replay</title>
<style>
body{font:13px Helvetica,Arial,sans-serif;margin:0;color:#222;background:#fafafa}
header{padding:6px 12px;background:#28435e;color:#fff;display:flex;gap:16px;align-items:center}
header h1{font-size:16px;margin:0}
#controls{padding:6px 12px;display:flex;gap:10px;align-items:center;background:#eef2f6}
#scrubber{flex:1}
main{display:flex;gap:8px;padding:8px}
#view{border:1px solid #999;background:#fff}
#side{flex:1;min-width:320px;display:flex;flex-direction:column;gap:8px}
.panel{background:#fff;border:1px solid #ccc;padding:6px;overflow:auto}
.panel h2{font-size:13px;margin:0 0 4px 0}
#tree{max-height:420px}
.node{white-space:nowrap;line-height:17px}
.node .dot{display:inline-block;width:10px;height:10px;border-radius:5px;margin-right:4px;
 background:#ddd;border:1px solid #999;vertical-align:-1px}
.node[data-status=SUCCESS] .dot{background:#2e9d3a}
.node[data-status=FAILURE] .dot{background:#d62728}
.node[data-status=RUNNING] .dot{background:#f28e00}
.node .type{font-weight:bold}.node .name{color:#555}
.kind-control .type{color:#2f5f98}.kind-decorator .type{color:#6a3d9a}
.kind-condition .type{color:#9a7b00}.kind-action .type{color:#2e7d32}
#bb table{border-collapse:collapse}#bb td{border-bottom:1px solid #eee;padding:1px 4px;
 font-family:monospace;font-size:11px;vertical-align:top}
#events{max-height:120px;font-family:monospace;font-size:11px}
label{user-select:none}
</style></head>
<body>
<header><h1>__TITLE__</h1><span id="outcome"></span></header>
<div id="controls">
 <button id="play">play</button>
 <input type="range" id="scrubber" min="0" max="0" value="0" step="1">
 <span>tick <b id="tick">0</b></span> <span>t = <b id="time">0</b> s</span>
 <span>pose <b id="pose"></b></span><span>root <b id="root"></b></span>
</div>
<div id="controls2" style="padding:2px 12px;background:#eef2f6">
 <label><input type="checkbox" id="show-global" checked> global costmap</label>
 <label><input type="checkbox" id="show-local" checked> local costmap</label>
 <label><input type="checkbox" id="show-laser" checked> laser</label>
 <label><input type="checkbox" id="show-particles" checked> particles</label>
 <label><input type="checkbox" id="show-path" checked> path</label>
</div>
<main>
 <canvas id="view" width="760" height="600"></canvas>
 <div id="side">
  <div class="panel" id="tree"><h2>Tree</h2><div id="nodes"></div></div>
  <div class="panel" id="bb"><h2>Blackboard</h2><table id="bbtable"></table></div>
  <div class="panel" id="events"><h2>Events</h2><div id="eventlist"></div></div>
 </div>
</main>
<script id="run-data" type="application/json">__DATA__</script>
<script>
"use strict";
const D = JSON.parse(document.getElementById("run-data").textContent);
const N = D.ticks.length, M = D.nodes.length;
const $ = (id) => document.getElementById(id);
function b64i16(s){const b=atob(s);const u=new Uint8Array(b.length);
 for(let i=0;i<b.length;i++)u[i]=b.charCodeAt(i);return new Int16Array(u.buffer);}
function lastAtOrBefore(list,i){let lo=0,hi=list.length-1,best=-1;
 while(lo<=hi){const m=(lo+hi)>>1;if(list[m][0]<=i){best=m;lo=m+1}else hi=m-1}
 return best<0?null:list[best];}
// node statuses at every tick, from the recorded changes
const CODES=["INVALID","RUNNING","SUCCESS","FAILURE"];
const status=new Uint8Array(Math.max(1,N*M));
{let cur=new Uint8Array(M),k=0;
 for(let i=0;i<N;i++){while(k<D.status.length&&D.status[k][0]===i){
   for(const [n,s] of Object.entries(D.status[k][1]))cur[+n]=Math.max(0,CODES.indexOf(s));k++;}
  status.set(cur,i*M);}}
// blackboard: per key, its changes
const bbKeys={};for(const [i,ch] of D.bb)for(const [k,v] of Object.entries(ch))
 (bbKeys[k]=bbKeys[k]||[]).push([i,v]);
const images={};
function img(uri){if(!images[uri]){const im=new Image();im.onload=draw;im.src=uri;images[uri]=im;}
 return images[uri];}
const scans=(D.scans||[]).map(([i,lp,b])=>[i,lp,b64i16(b)]);
const parts=(D.particles||[]).map(([i,b])=>[i,b64i16(b)]);
// paths: [x0, y0, int16 centimetres from (x0, y0)] (path_code), or a plain list of points
const paths=(D.paths||[]).map(([i,p])=>{if(p.length!==3||typeof p[2]!=="string")return [i,p];
 const v=b64i16(p[2]),q=[];for(let k=0;k+1<v.length;k+=2)q.push([p[0]+v[k]/100,p[1]+v[k+1]/100]);
 return [i,q];});
// the view: the run's box fitted into the canvas
const cv=$("view"),ctx=cv.getContext("2d");
const [bx0,by0,bx1,by1]=D.box;
const sc=Math.min(cv.width/(bx1-bx0),cv.height/(by1-by0));
const offx=(cv.width-(bx1-bx0)*sc)/2,offy=(cv.height-(by1-by0)*sc)/2;
const X=(x)=>offx+(x-bx0)*sc, Y=(y)=>cv.height-offy-(y-by0)*sc;
function grid(g){const im=img(g.png);if(im.complete&&im.naturalWidth){
 ctx.imageSmoothingEnabled=false;
 ctx.drawImage(im,X(g.ox),Y(g.oy+g.h*g.res),g.w*g.res*sc,g.h*g.res*sc);}}
function poly(pts,colour,width){if(pts.length<2)return;ctx.strokeStyle=colour;
 ctx.lineWidth=width;ctx.beginPath();ctx.moveTo(X(pts[0][0]),Y(pts[0][1]));
 for(const p of pts.slice(1))ctx.lineTo(X(p[0]),Y(p[1]));ctx.stroke();}
function footprint(p,colour){if(!p)return;const c=Math.cos(p[2]),s=Math.sin(p[2]);
 const fp=D.footprint.length?D.footprint:[[0.2,0.2],[0.2,-0.2],[-0.2,-0.2],[-0.2,0.2]];
 const pts=fp.map(([fx,fy])=>[p[0]+c*fx-s*fy,p[1]+s*fx+c*fy]);pts.push(pts[0]);
 poly(pts,colour,2);poly([[p[0],p[1]],[p[0]+0.35*c,p[1]+0.35*s]],colour,2);}
let cur=0;
function draw(){
 const i=cur;ctx.fillStyle="#fff";ctx.fillRect(0,0,cv.width,cv.height);
 if(D.map)grid(D.map);
 if($("show-global").checked){const g=lastAtOrBefore(D.global_costmaps||[],i);if(g)grid(g[1]);}
 if($("show-local").checked){const g=lastAtOrBefore(D.local_costmaps||[],i);if(g)grid(g[1]);}
 const traj=D.pose.filter(p=>p);poly(traj,"rgba(20,150,40,0.25)",1);
 poly(D.pose.slice(0,i+1).filter(p=>p),"rgb(20,150,40)",2);
 if(D.truth)poly(D.truth.slice(0,i+1),"rgba(0,0,0,0.5)",1);
 if($("show-path").checked){const p=lastAtOrBefore(paths,i);if(p)poly(p[1],"rgb(60,110,230)",2);}
 if($("show-particles").checked){const p=lastAtOrBefore(parts,i);if(p){ctx.fillStyle="rgba(200,0,0,0.6)";
  for(let k=0;k<p[1].length;k+=2)ctx.fillRect(X(p[1][k]/100)-1,Y(p[1][k+1]/100)-1,2,2);}}
 if($("show-laser").checked){const s=lastAtOrBefore(scans,i);if(s){ctx.fillStyle="rgb(230,0,90)";
  for(let k=0;k<s[2].length;k+=2)ctx.fillRect(X(s[2][k]/100)-1.5,Y(s[2][k+1]/100)-1.5,3,3);}}
 for(const g of D.goals){footprint(g,"rgb(160,0,200)");}
 footprint(D.pose[i],"rgb(0,90,200)");
 // scale bar
 let m=1;for(const c of [0.5,1,2,5,10,20,50]){if(c*sc<=cv.width/4)m=c;}
 ctx.fillStyle="rgba(255,255,255,0.85)";ctx.fillRect(8,cv.height-30,m*sc+16,24);
 ctx.fillStyle="#000";ctx.fillRect(16,cv.height-14,m*sc,4);ctx.font="11px sans-serif";
 ctx.fillText(m+" m",16,cv.height-18);
}
function fmt(v){const s=JSON.stringify(v);return s&&s.length>90?s.slice(0,87)+"...":s;}
function show(i){
 cur=Math.max(0,Math.min(N-1,i|0));$("scrubber").value=cur;
 $("tick").textContent=D.ticks[cur];$("time").textContent=(+D.t[cur]).toFixed(2);
 const p=D.pose[cur];$("pose").textContent=p?p.map(v=>(+v).toFixed(2)).join(", "):"-";
 $("root").textContent=D.root[cur];
 for(let n=0;n<M;n++)$("node-"+n).dataset.status=CODES[status[cur*M+n]];
 const rows=[];for(const k of Object.keys(bbKeys).sort()){const c=lastAtOrBefore(bbKeys[k],cur);
  if(c)rows.push("<tr><td>"+k+"</td><td>"+escape(fmt(c[1]))+"</td></tr>");}
 $("bbtable").innerHTML=rows.join("");
 const ev=[];for(const [j,list] of D.events){if(j>cur)break;for(const e of list)
  ev.push(D.ticks[j]+": "+escape(JSON.stringify(e)));}
 $("eventlist").innerHTML=ev.slice(-40).reverse().join("<br>");
 draw();}
function escape(s){return String(s).replace(/&/g,"&amp;").replace(/</g,"&lt;");}
{const out=[];D.nodes.forEach(([name,type,depth,kind],n)=>{out.push('<div class="node kind-'+kind+
 '" id="node-'+n+'" data-status="INVALID" style="padding-left:'+(depth*14)+'px"><span class="dot">'+
 '</span><span class="type">'+escape(type)+'</span>'+(name!==type?' <span class="name">'+
 escape(name)+'</span>':'')+'</div>');});$("nodes").innerHTML=out.join("");}
if(D.footer&&D.footer.outcome)$("outcome").textContent=D.footer.outcome+" in "+D.footer.time_s+
 " s, recoveries: "+((D.footer.recoveries||[]).join(", ")||"none");
$("scrubber").max=Math.max(0,N-1);
$("scrubber").addEventListener("input",e=>show(+e.target.value));
for(const id of ["show-global","show-local","show-laser","show-particles","show-path"])
 $(id).addEventListener("change",draw);
let timer=null;$("play").addEventListener("click",()=>{if(timer){clearInterval(timer);timer=null;
 $("play").textContent="play";return;}$("play").textContent="pause";
 timer=setInterval(()=>{if(cur>=N-1){clearInterval(timer);timer=null;$("play").textContent="play";}
 else show(cur+1);},Math.max(10,1000*(D.period||0.1)));});
document.addEventListener("keydown",e=>{if(e.target.tagName==="INPUT"&&e.target.type==="range")return;
 if(e.key==="ArrowRight")show(cur+1);if(e.key==="ArrowLeft")show(cur-1);});
show(0);
</script></body></html>
"""


def _decode_png(uri: str) -> Image.Image:
    return Image.open(io.BytesIO(base64.b64decode(uri.split(",", 1)[1]))).convert("RGBA")


def _last_at_or_before(items: list[list[Any]], i: int) -> Any:
    best = None
    for item in items:
        if item[0] <= i:
            best = item
        else:
            break
    return best


def draw_frame(data: dict[str, Any], i: int, out_path: str, width: int = 760,
               height: int = 600) -> Image.Image:
    """One frame of the replay (what the page shows at tick index ``i``) as a PNG."""
    from PIL import ImageDraw

    from executive.draw_run import _font
    from executive.recorder import statuses_at
    n = len(data["ticks"])
    if not 0 <= i < n:
        raise ValueError(f"tick index {i} out of range 0..{n - 1}")
    bx0, by0, bx1, by1 = data["box"]
    sc = min(width / (bx1 - bx0), height / (by1 - by0))
    offx, offy = (width - (bx1 - bx0) * sc) / 2, (height - (by1 - by0) * sc) / 2

    def X(x: float) -> float:
        return offx + (x - bx0) * sc

    def Y(y: float) -> float:
        return height - offy - (y - by0) * sc

    side = 300
    img = Image.new("RGBA", (width, height), (255, 255, 255, 255))  # the map view alone

    def grid(g: dict[str, Any]) -> None:
        im = _decode_png(g["png"])
        w, h = max(1, round(g["w"] * g["res"] * sc)), max(1, round(g["h"] * g["res"] * sc))
        im = im.resize((w, h), Image.NEAREST)
        img.alpha_composite(im, (round(X(g["ox"])), round(Y(g["oy"] + g["h"] * g["res"]))))

    if "map" in data:
        grid(data["map"])
    for key in ("global_costmaps", "local_costmaps"):
        g = _last_at_or_before(data.get(key, []), i)
        if g is not None:
            grid(g[1])
    draw = ImageDraw.Draw(img)
    poses = [p for p in data["pose"][: i + 1] if p]
    if len(poses) >= 2:
        draw.line([(X(p[0]), Y(p[1])) for p in poses], fill=(20, 150, 40), width=2)
    path = _last_at_or_before(data["paths"], i)
    points = path_points(path[1]) if path is not None else []
    if len(points) >= 2:
        draw.line([(X(p[0]), Y(p[1])) for p in points], fill=(60, 110, 230), width=2)
    parts = _last_at_or_before(data.get("particles", []), i)
    if parts is not None:
        xy = np.frombuffer(base64.b64decode(parts[1]), "<i2").reshape(-1, 2) / 100.0
        for x, y in xy:
            draw.rectangle([X(x) - 1, Y(y) - 1, X(x) + 1, Y(y) + 1], fill=(200, 0, 0))
    scan = _last_at_or_before(data.get("scans", []), i)
    if scan is not None:
        xy = np.frombuffer(base64.b64decode(scan[2]), "<i2").reshape(-1, 2) / 100.0
        for x, y in xy:
            draw.rectangle([X(x) - 1, Y(y) - 1, X(x) + 1, Y(y) + 1], fill=(230, 0, 90))
    fp = data.get("footprint") or [[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]

    def footprint(p: Sequence[float], colour: tuple[int, int, int]) -> None:
        c, s = math.cos(p[2]), math.sin(p[2])
        pts = [(X(p[0] + c * fx - s * fy), Y(p[1] + s * fx + c * fy)) for fx, fy in fp]
        draw.line(pts + [pts[0]], fill=colour, width=2)
        draw.line([(X(p[0]), Y(p[1])), (X(p[0] + 0.35 * c), Y(p[1] + 0.35 * s))], fill=colour,
                  width=2)

    for g in data.get("goals", []):
        footprint(g, (160, 0, 200))
    if data["pose"][i]:
        footprint(data["pose"][i], (0, 90, 200))
    # the tree's statuses beside the map (drawn on a wider picture: nothing of the map view
    # spills into the side panel)
    frame = Image.new("RGBA", (width + side, height), (255, 255, 255, 255))
    frame.paste(img, (0, 0))
    img = frame
    draw = ImageDraw.Draw(img)
    f12 = _font(12)
    colours = {"SUCCESS": (46, 157, 58), "FAILURE": (214, 39, 40), "RUNNING": (242, 142, 0)}
    header = {"nodes": [n[:3] for n in data["nodes"]]}
    ticks = [{"tick": t, "status": {}} for t in data["ticks"]]
    for j, changes in data["status"]:
        ticks[j]["status"] = changes
    statuses = statuses_at(header, ticks, data["ticks"][i])
    x0, y = width + 8, 6
    pose = data["pose"][i]
    head = f"tick {data['ticks'][i]}  t={data['t'][i]:.2f} s"
    draw.text((x0, y), head, fill=(0, 0, 0), font=_font(14))
    y += 18
    if pose:
        draw.text((x0, y), f"pose {pose[0]:.2f}, {pose[1]:.2f}, {pose[2]:.2f}", fill=(0, 0, 0),
                  font=f12)
        y += 18
    for (name, type_name, depth, _), st in zip(data["nodes"], statuses):
        if y > height - 14:
            break
        colour = colours.get(st, (200, 200, 200))
        draw.ellipse([x0 + depth * 10, y + 2, x0 + depth * 10 + 9, y + 11], fill=colour)
        label = type_name if name == type_name else f"{type_name} {name}"
        draw.text((x0 + depth * 10 + 13, y), label[:40], fill=(0, 0, 0), font=f12)
        y += 14
    img = img.convert("RGB")
    img.save(out_path)
    return img
