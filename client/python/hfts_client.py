#!/usr/bin/env python3
"""Client of the hfts planning service (hfts-server, docs/protocol.md).

Standard library only. One TCP connection, JSON-RPC 2.0, one message per
line. Calls block until their answer arrives; send() and receive() let a
caller pipeline requests (and cancel a plan while it runs).

When the connection fails before a call's answer arrives (the server died,
a balancer dropped the connection, nothing listens yet), call() and the
methods built on it connect again and send the call again, up to
`retries` times with a doubling backoff: a plan is determined by its seed,
so repeating it is safe. cancel() and shutdown() are never repeated (a
cancel's id belongs to the lost connection; a repeated shutdown would
reach another instance behind a balancer), nor are send()/receive().

    from hfts_client import HftsClient

    with HftsClient("127.0.0.1", 7450) as client:
        plan = client.plan(scene="table", time_limit=10, seed=1)
        if plan["success"]:
            print(plan["grasp"]["epsilon"], len(plan["path"]), plan["joint_names"])

A server started with --auth-tokens wants a token (docs/security.md):
HftsClient(..., token=...) sends it with `auth` on every connection it makes.
HftsClient(..., tls=True, ca_file=...) speaks TLS and verifies the server's
certificate (against ca_file, else the system's CAs) and host name.

As a program: hfts_client.py [--host H] [--port P] [--token-file F] [--tls] [--ca-file F]
info|objects|scenes|shutdown
or hfts_client.py plan SCENE [--object NAME] [--time-limit S] [--seed N];
it prints the JSON result.
"""

import argparse
import base64
import itertools
import json
import os
import socket
import ssl
import sys
import time

DEFAULT_PORT = 7450


class RpcError(Exception):
    """An error response: code (docs/protocol.md), message and the offending field (or None)."""

    def __init__(self, code, message, field=None):
        super().__init__(f"{message} (error {code})")
        self.code = code
        self.message = message
        self.field = field


NOT_REPEATED = {"cancel", "shutdown"}


class HftsClient:
    def __init__(self, host="127.0.0.1", port=DEFAULT_PORT, timeout=None, retries=2, backoff=0.2,
                 token=None, tls=False, ca_file=None):
        """retries: further attempts when the connection fails before an answer
        (0: none); backoff: seconds before the first, doubling up to 2 s;
        token: sent with `auth` on every connection (a server with tokens);
        tls: speak TLS, verifying the server's certificate against ca_file
        (PEM; None: the system's CAs) and its host name (ca_file implies tls)."""
        if retries < 0 or backoff < 0:
            raise ValueError("retries and backoff must be >= 0")
        self._token = token
        self._tls = ssl.create_default_context(cafile=ca_file) if tls or ca_file else None
        self._address = (host, port)
        self._timeout = timeout
        self._retries = retries
        self._backoff = backoff
        self.reconnections = 0  # connections made again after a failure
        self._ids = itertools.count(1)
        self._socket = self._reader = None
        self._with_retries(True, self._connect)

    def _connect(self):
        self._socket = socket.create_connection(self._address, timeout=self._timeout)
        self._socket.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        if self._tls is not None:
            try:
                self._socket = self._tls.wrap_socket(self._socket,
                                                     server_hostname=self._address[0])
            except ssl.SSLCertVerificationError:
                self._socket.close()
                self._socket = None
                raise  # not a lost connection: another attempt would not verify either
        self._reader = self._socket.makefile("rb")
        self._waiting = {}  # responses that arrived for other ids
        if self._token:
            message = {"jsonrpc": "2.0", "id": "auth", "method": "auth",
                       "params": {"token": self._token}}
            self._socket.sendall(json.dumps(message).encode() + b"\n")
            self.receive("auth")

    def _with_retries(self, allowed, attempt):
        """Runs attempt() until it does not lose the connection, at most 1 + retries times."""
        attempts = 1 + self._retries if allowed else 1
        wait = self._backoff
        for n in itertools.count(1):
            try:
                return attempt()
            except ConnectionError:
                self.close()  # the next call connects again
                if n >= attempts:
                    raise
                time.sleep(wait)
                wait = min(2 * wait, 2.0)
                self.reconnections += 1

    def close(self):
        if self._reader is not None:
            self._reader.close()
            self._socket.close()
            self._reader = self._socket = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def send(self, method, params=None):
        """Sends a request without waiting; returns its id (for receive() and cancel())."""
        if self._socket is None:  # a failed call left no connection
            self._connect()
        request_id = next(self._ids)
        message = {"jsonrpc": "2.0", "id": request_id, "method": method, "params": params or {}}
        self._socket.sendall(json.dumps(message).encode() + b"\n")
        return request_id

    def receive(self, request_id):
        """Waits for the response to request_id; returns its result or raises RpcError."""
        while request_id not in self._waiting:
            line = self._reader.readline()
            if not line:
                raise ConnectionResetError("the server closed the connection")
            if not line.endswith(b"\n"):
                # The connection ended in the middle of a response (the
                # instance behind a proxy was killed while writing it).
                raise ConnectionResetError("the server closed the connection within a response")
            response = json.loads(line)
            key = response.get("id")
            self._waiting[request_id if key is None else key] = response
        response = self._waiting.pop(request_id)
        if "error" in response:
            error = response["error"]
            raise RpcError(error["code"], error["message"], error.get("data", {}).get("field"))
        return response["result"]

    def call(self, method, params=None):
        """Sends a request and waits for its result (raises RpcError); repeated on a
        lost connection unless the method is cancel or shutdown."""
        def attempt():
            return self.receive(self.send(method, params))
        return self._with_retries(method not in NOT_REPEATED, attempt)

    def info(self):
        return self.call("server.info")

    def objects(self, robot=None):
        """The object databases, graspability for `robot` (default: the server's first)."""
        return self.call("objects.list", {"robot": robot} if robot else None)

    def scenes(self, robot=None):
        """The scenes, their start for `robot` (default: the server's first)."""
        return self.call("scenes.list", {"robot": robot} if robot else None)

    def plan(self, scene, **options):
        """Plans a grasp and a path. scene: a scene name or an inline scene (dict);
        options: robot, object, object_pose, start, time_limit, algorithm, iterations, seed,
        parameters, trajectory_rate, format ("ros": also the plan as ROS messages)
        (docs/protocol.md); goal or goals (joint_goal(),
        pose_goal()) plan a motion to them instead of a grasp; obstacles: more
        obstacles for the scene, e.g. [depth_image(...)]."""
        return self.call("plan", plan_params(scene, **options))

    def plan_async(self, scene, **options):
        """Sends a plan request and returns its id; receive(id) gets the result."""
        return self.send("plan", plan_params(scene, **options))

    def cancel(self, request_id):
        """Cancels a plan sent on this connection; True when it was still queued or running."""
        return self.call("cancel", {"id": request_id})["cancelled"]

    def quality(self, contacts, **options):
        """Ferrari-Canny epsilon; contacts: [{"position": [..], "normal": [..]}, ...];
        options: normals, center, torque_scale, friction, cone_edges, object."""
        return self.call("grasp.quality", {"contacts": contacts, **options})["epsilon"]

    def reload(self):
        return self.call("reload")

    def shutdown(self):
        return self.call("shutdown")


def joint_goal(joints):
    """A motion goal (plan's goal/goals): a configuration, every DoF or the arm's."""
    return {"joints": [float(v) for v in joints]}


def pose_goal(position, orientation, link=None, position_tolerance=None,
              orientation_tolerance=None):
    """A motion goal: the palm (or link, the flange or the palm) at position [x, y, z] and
    orientation [qx, qy, qz, qw] in the world frame, within the tolerances (m, rad)."""
    goal = {"pose": {"position": [float(v) for v in position],
                     "orientation": [float(v) for v in orientation]}}
    for name, value in (("link", link), ("position_tolerance", position_tolerance),
                        ("orientation_tolerance", orientation_tolerance)):
        if value is not None:
            goal[name] = value
    return goal


PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
NPY_MAGIC = b"\x93NUMPY"
IMAGE_KEYS = ("type", "file", "png_base64", "npy_base64", "mask", "mask_base64")


def depth_image(image, camera, mask=None):
    """A depth_image obstacle (plan's obstacles, docs/point_clouds.md) from the bytes of a
    16-bit PNG or a float32 .npy (image), the camera's keys (camera: intrinsics and pose
    required; name, default "camera"; units, default mm for a PNG, m for a .npy; min_depth,
    max_depth, voxel, radius, shadow, outliers) and an 8-bit mask PNG's bytes (mask), as
    hfts-client plan --depth FILE --camera JSON --mask FILE sends it. Raises ValueError."""
    is_png = image.startswith(PNG_MAGIC)
    if not is_png and not image.startswith(NPY_MAGIC):
        raise ValueError("the depth image is neither a PNG nor a NumPy .npy file")
    missing = [key for key in ("intrinsics", "pose") if key not in camera]
    taken = [key for key in IMAGE_KEYS if key in camera]
    if missing or taken:
        raise ValueError(f"the camera lacks {missing} or has the image's keys {taken}")
    view = {"type": "depth_image", "name": "camera", "units": "mm" if is_png else "m",
            **camera, ("png_base64" if is_png else "npy_base64"): base64.b64encode(image).decode()}
    if mask is not None:
        if not mask.startswith(PNG_MAGIC):
            raise ValueError("the mask is not a PNG")
        view["mask_base64"] = base64.b64encode(mask).decode()
    return view


def plan_params(scene, **options):
    params = {"scene": scene}
    params.update({k: v for k, v in options.items() if v is not None})
    return params


def parameters_of(parser, pairs):
    """The --param NAME=VALUE pairs as the request's parameters (None when
    there are none); a pair without '=' is a usage error."""
    parameters = {}
    for pair in pairs:
        name, sep, value = pair.partition("=")
        if not sep or not name:
            parser.error(f"--param: expected NAME=VALUE, got '{pair}'")
        parameters[name] = value
    return parameters or None


def goals_of(parser, joints, poses):
    """The --goal-joints / --goal-pose values as the request's goals (None when there are
    none); a value that is not a list of numbers is a usage error."""
    goals = []
    for flag, texts, make in (("--goal-joints", joints, joint_goal),
                              ("--goal-pose", poses, lambda v: pose_goal(v[:3], v[3:]))):
        for text in texts:
            try:
                values = [float(v) for v in text.split(",")]
            except ValueError:
                parser.error(f"{flag}: expected comma-separated numbers, got '{text}'")
            if flag == "--goal-pose" and len(values) != 7:
                parser.error(f"--goal-pose: expected x,y,z,qx,qy,qz,qw, got '{text}'")
            goals.append(make(values))
    return goals or None


def token_from(token_file):
    """The first line of token_file when given, else $HFTS_TOKEN, else None."""
    if token_file is None:
        return os.environ.get("HFTS_TOKEN", "").strip() or None
    with open(token_file, encoding="utf-8") as f:
        token = f.readline().strip()
    if not token:
        raise ValueError(f"{token_file} holds no token on its first line")
    return token


def main(argv=None):
    parser = argparse.ArgumentParser(description="hfts-server client (prints JSON results)")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=DEFAULT_PORT)
    parser.add_argument("--token-file", metavar="FILE",
                        help="the token for a server with --auth-tokens (default: $HFTS_TOKEN)")
    parser.add_argument("--tls", action="store_true",
                        help="speak TLS; the server's certificate must verify")
    parser.add_argument("--ca-file", metavar="FILE",
                        help="verify the server's certificate against these CAs (implies --tls)")
    parser.add_argument("--retries", type=int, default=2,
                        help="attempts again when the connection fails before the answer")
    parser.add_argument("command", choices=["info", "objects", "scenes", "plan", "shutdown"])
    parser.add_argument("scene", nargs="?", help="plan: the scene name")
    parser.add_argument("--robot", help="a robot of the server (default: its first)")
    parser.add_argument("--object")
    parser.add_argument("--time-limit", type=float)
    parser.add_argument("--seed", type=int)
    parser.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                        help="plan: a planner parameter (docs/planning.md), repeatable")
    parser.add_argument("--goal-joints", action="append", default=[], metavar="Q1,Q2,...",
                        help="plan: a motion to this configuration instead of a grasp, repeatable")
    parser.add_argument("--goal-pose", action="append", default=[], metavar="X,Y,Z,QX,QY,QZ,QW",
                        help="plan: a motion putting the palm at this world pose, repeatable")
    args = parser.parse_args(argv)
    try:
        token = token_from(args.token_file)
        with HftsClient(args.host, args.port, retries=args.retries, token=token, tls=args.tls,
                        ca_file=args.ca_file) as client:
            if args.command == "plan":
                if not args.scene:
                    parser.error("plan needs a scene")
                result = client.plan(args.scene, robot=args.robot, object=args.object,
                                     time_limit=args.time_limit, seed=args.seed,
                                     parameters=parameters_of(parser, args.param),
                                     goals=goals_of(parser, args.goal_joints, args.goal_pose))
            elif args.command in ("objects", "scenes"):
                result = getattr(client, args.command)(args.robot)
            else:
                result = getattr(client, args.command)()
    except (RpcError, OSError, ValueError) as e:
        print(f"hfts_client: {e}", file=sys.stderr)
        return 1
    print(json.dumps(result, indent=2))
    return 0 if args.command != "plan" or result["success"] else 3


if __name__ == "__main__":
    sys.exit(main())
