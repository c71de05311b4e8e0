#!/usr/bin/env python3
"""Send the ROS 2 export of a pushpack plan to a robot.

    pushpack export out/plan.json --format ros2-goal --out goals/
    python3 scripts/ros2_send.py goals/                 # blocking: step by step (default)
    python3 scripts/ros2_send.py goals/ --mode timed    # both arms' whole goals, grippers on time
    python3 scripts/ros2_send.py goals/ --dry-run       # print what would be sent, as JSON; no ROS

The goals are read from the files that `goals/ros2_goals.yaml` names and handed to rclpy's
action clients as messages, never through a command line: one arm's goal for exp2 is 0.7 MB,
and one shell argument may hold 128 KiB.

Modes:
* `blocking` runs `action_list.yaml`: each `trajectories` step sends one
  FollowJointTrajectory goal per arm together and waits for both results; each `gripper` step
  sends one GripperCommand goal and waits for it. The arms are at rest at every gripper step.
* `timed` sends `<arm>_arm_goal.yaml` to each arm's controller with one common start stamp
  (`--lead` seconds ahead, so both arms start together), then each GripperCommand of
  `gripper_commands.yaml` at its `time_from_start` after that start, without waiting for the
  gripper: use it only with a gripper that is faster than the plan's dwell at a grasp.

`--dry-run` needs no ROS (only PyYAML): it prints every goal as the dict that would fill the
message, with the action server's name and type, in sending order. tests/export.rs reads that
output back into structs that mirror the message definitions field for field.
"""

import argparse
import json
import pathlib
import sys

import yaml

FJT = "control_msgs/action/FollowJointTrajectory"
GRIPPER = "control_msgs/action/GripperCommand"
ZERO = {"sec": 0, "nanosec": 0}


def load_yaml(path):
    loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    with open(path, encoding="utf-8") as f:
        return yaml.load(f, Loader=loader)


def empty_rest():
    """The goal fields after `trajectory`: no tolerances beyond the controller's own."""
    return {
        "multi_dof_trajectory": {
            "header": {"stamp": dict(ZERO), "frame_id": ""},
            "joint_names": [],
            "points": [],
        },
        "path_tolerance": [],
        "component_path_tolerance": [],
        "goal_tolerance": [],
        "component_goal_tolerance": [],
        "goal_time_tolerance": dict(ZERO),
    }


def arm_goal(frame_id, piece):
    """A whole FollowJointTrajectory goal from one arm's piece of the blocking list."""
    points = [
        {
            "positions": p["positions"],
            "velocities": p["velocities"],
            "accelerations": [],
            "effort": [],
            "time_from_start": p["time_from_start"],
        }
        for p in piece["points"]
    ]
    goal = {
        "trajectory": {
            "header": {"stamp": dict(ZERO), "frame_id": frame_id},
            "joint_names": piece["joint_names"],
            "points": points,
        }
    }
    goal.update(empty_rest())
    return goal


def batches(directory, mode):
    """What to send, in order: a list of {"at": seconds or None, "goals": [...]} where each goal
    is {"action": server, "type": action type, "goal": dict}. `at` is the time after the common
    start in timed mode; in blocking mode a batch is sent when the previous one has finished."""
    d = pathlib.Path(directory)
    manifest = load_yaml(d / "ros2_goals.yaml")
    arms = {a["arm"]: a for a in manifest["arms"]}
    frame_id = manifest["frame_id"]
    gripper_goal = lambda step: {  # noqa: E731
        "action": arms[step["arm"]]["gripper_action"],
        "type": GRIPPER,
        "goal": {"command": step["command"]},
    }
    out = []
    if mode == "timed":
        goals = [
            {"action": a["action"], "type": FJT, "goal": load_yaml(d / a["goal"])}
            for a in manifest["arms"]
        ]
        out.append({"at": 0.0, "goals": goals})
        for step in load_yaml(d / manifest["gripper_commands"])["steps"] or []:
            t = step["time_from_start"]
            out.append({"at": t["sec"] + t["nanosec"] * 1e-9, "goals": [gripper_goal(step)]})
        return out
    for step in load_yaml(d / manifest["action_list"])["steps"] or []:
        if "trajectories" in step:
            goals = [
                {"action": arms[p["arm"]]["action"], "type": FJT, "goal": arm_goal(frame_id, p)}
                for p in step["trajectories"]
            ]
        else:
            goals = [gripper_goal(step["gripper"])]
        out.append({"at": None, "goals": goals})
    return out


def send(plan, mode, lead):  # pragma: no cover - needs a running ROS 2 graph
    import rclpy
    from rclpy.action import ActionClient
    from rclpy.duration import Duration
    from rosidl_runtime_py.set_message import set_message_fields
    from control_msgs.action import FollowJointTrajectory, GripperCommand

    types = {FJT: FollowJointTrajectory, GRIPPER: GripperCommand}
    rclpy.init()
    node = rclpy.create_node("pushpack_sender")
    clients = {}
    for b in plan:
        for g in b["goals"]:
            if g["action"] not in clients:
                c = ActionClient(node, types[g["type"]], g["action"])
                if not c.wait_for_server(timeout_sec=10.0):
                    sys.exit(f"error: no action server {g['action']} ({g['type']}) after 10 s")
                clients[g["action"]] = c

    def message(g, stamp=None):
        msg = types[g["type"]].Goal()
        set_message_fields(msg, g["goal"])
        if stamp is not None:
            msg.trajectory.header.stamp = stamp
        return msg

    def wait(future):
        rclpy.spin_until_future_complete(node, future)
        return future.result()

    def run(goals, stamp=None):
        handles = [wait(clients[g["action"]].send_goal_async(message(g, stamp))) for g in goals]
        for g, h in zip(goals, handles):
            if not h.accepted:
                sys.exit(f"error: {g['action']} rejected the goal")
        return handles

    def finish(goals, handles):
        for g, h in zip(goals, handles):
            r = wait(h.get_result_async()).result
            code = getattr(r, "error_code", 0)
            if code != 0:
                sys.exit(f"error: {g['action']} failed with error_code {code}: {getattr(r, 'error_string', '')}")

    if mode == "timed":
        start = node.get_clock().now() + Duration(seconds=lead)
        arms = plan[0]["goals"]
        handles = run(arms, start.to_msg())
        for b in plan[1:]:
            due = start + Duration(seconds=b["at"])
            while node.get_clock().now() < due:
                rclpy.spin_once(node, timeout_sec=0.005)
            run(b["goals"])
        finish(arms, handles)
    else:
        for b in plan:
            finish(b["goals"], run(b["goals"]))
    node.destroy_node()
    rclpy.shutdown()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("directory", help="the --out directory of `pushpack export --format ros2-goal`")
    ap.add_argument("--mode", choices=["blocking", "timed"], default="blocking")
    ap.add_argument("--lead", type=float, default=0.5, help="timed mode: seconds before the common start")
    ap.add_argument("--dry-run", action="store_true", help="print what would be sent as JSON; no ROS needed")
    args = ap.parse_args(argv)
    try:
        plan = batches(args.directory, args.mode)
    except (OSError, KeyError, TypeError, yaml.YAMLError) as e:
        print(f"error: {args.directory}: not a complete ros2-goal export ({type(e).__name__}: {e})", file=sys.stderr)
        return 2
    if args.dry_run:
        json.dump({"mode": args.mode, "batches": plan}, sys.stdout)
        print()
        return 0
    send(plan, args.mode, args.lead)
    return 0


if __name__ == "__main__":
    sys.exit(main())
