"""Resting poses of objects measured by two independent tools (for `cargo xtask stability`).

Reads a JSON job (argv[1]):
    {"drops": N, "seed": S, "objects": [{"name": str, "vertices": [[x, y, z], ...],
      "faces": [[i, j, k], ...], "cog": [x, y, z]}, ...]}
the object's convex hull in its own frame (metres) and its centre of gravity, and writes
(argv[2]) a JSON result:
    {"pybullet": "3.2.7", "trimesh": "4.12.2", "objects": [{"name": str,
      "drops": {"poses": [{"down": [x, y, z], "count": k, "frequency": f}, ...],
                "unsettled": n},
      "trimesh": {"poses": [{"down": [x, y, z], "probability": p}, ...]}}, ...]}
with every `down` the world's -z expressed in the object frame (the outward normal of the
support facet).

pybullet: N drops per object from random orientations (seeded per object: `seed` and the
object's name), the lowest point 1 cm above a plane, friction 0.8 on both bodies, no
restitution, the object's convex hull as its collider with the centre of mass at `cog`,
steps of 1/240 s until at rest (at least 1 s, then linear speed < 1 mm/s and angular
< 0.005 rad/s for 0.5 s: an object left on a nearly neutral facet starts rolling slowly, and
a looser test took such a pause for a rest) or 6 s, sleeping (deactivation) disabled,
angular damping 0.3 (a round-bottomed object such as the duck otherwise rocks for many
seconds; damping changes no equilibrium). Drops not at rest after 6 s are counted as
unsettled and left out of the clusters; frequencies are shares of all N drops. The final downs are clustered greedily within 5 degrees (the direction with most
neighbours first, the cluster's direction their normalised mean).

trimesh: `trimesh.poses.compute_stable_poses(mesh, center_mass=cog)` (quasi-static toppling
from a uniform sphere of directions; deterministic with the default sigma 0).
"""

import hashlib
import json
import math
import multiprocessing
import sys

import numpy as np

CLUSTER_DEG = 5.0
DT = 1.0 / 240.0
MIN_STEPS = int(1.0 / DT)
MAX_STEPS = int(6.0 / DT)
ANGULAR_DAMPING = 0.3
REST_STEPS = int(0.5 / DT)
REST_LINEAR = 0.001
REST_ANGULAR = 0.005
FRICTION = 0.8


def object_seed(seed, name):
    digest = hashlib.sha256(f"{seed}:{name}".encode()).digest()
    return int.from_bytes(digest[:8], "little")


def random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def cluster(downs):
    """Greedy clustering within CLUSTER_DEG: [(direction, count)], largest first."""
    downs = [d / np.linalg.norm(d) for d in downs]
    cos = math.cos(math.radians(CLUSTER_DEG))
    left = list(range(len(downs)))
    out = []
    while left:
        best, members = None, []
        for i in left:
            m = [j for j in left if float(np.dot(downs[i], downs[j])) >= cos]
            if len(m) > len(members):
                best, members = i, m
        mean = np.sum([downs[j] for j in members], axis=0)
        mean = mean / np.linalg.norm(mean)
        out.append((mean, len(members)))
        left = [j for j in left if j not in members]
    return out


def drop(obj, drops, seed):
    import pybullet as p

    client = p.connect(p.DIRECT)
    try:
        p.setGravity(0, 0, -9.81, physicsClientId=client)
        p.setTimeStep(DT, physicsClientId=client)
        plane_shape = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
        plane = p.createMultiBody(0, plane_shape, physicsClientId=client)
        p.changeDynamics(plane, -1, lateralFriction=FRICTION, restitution=0.0,
                         physicsClientId=client)
        cog = np.array(obj["cog"], dtype=float)
        # Body frame at the CoG, axes of the object frame.
        vertices = np.array(obj["vertices"], dtype=float) - cog
        shape = p.createCollisionShape(p.GEOM_MESH, vertices=vertices.tolist(),
                                       physicsClientId=client)
        body = p.createMultiBody(0.1, shape, basePosition=[0, 0, 1],
                                 physicsClientId=client)
        # No sleeping: Bullet deactivates a body slower than 0.8 m/s and 1 rad/s for 2 s by
        # default, which freezes a small object while it still rocks towards its rest.
        p.changeDynamics(body, -1, lateralFriction=FRICTION, restitution=0.0,
                         rollingFriction=0.0, spinningFriction=0.0,
                         activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                         angularDamping=ANGULAR_DAMPING,
                         physicsClientId=client)
        rng = np.random.default_rng(object_seed(seed, obj["name"]))
        downs, unsettled = [], 0
        for _ in range(drops):
            qw, qx, qy, qz = random_quaternion(rng)
            rot = np.array(p.getMatrixFromQuaternion([qx, qy, qz, qw])).reshape(3, 3)
            lowest = float(np.min((vertices @ rot.T)[:, 2]))
            p.resetBasePositionAndOrientation(body, [0, 0, 0.01 - lowest], [qx, qy, qz, qw],
                                              physicsClientId=client)
            p.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0], physicsClientId=client)
            still = 0
            for _step in range(MAX_STEPS):
                p.stepSimulation(physicsClientId=client)
                lin, ang = p.getBaseVelocity(body, physicsClientId=client)
                if np.linalg.norm(lin) < REST_LINEAR and np.linalg.norm(ang) < REST_ANGULAR:
                    still += 1
                    if still >= REST_STEPS and _step >= MIN_STEPS:
                        break
                else:
                    still = 0
            else:
                # Still rocking or rolling: no resting pose to record.
                unsettled += 1
                continue
            _, orn = p.getBasePositionAndOrientation(body, physicsClientId=client)
            rot = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)
            downs.append(rot.T @ np.array([0.0, 0.0, -1.0]))
        poses = [{"down": d.tolist(), "count": n, "frequency": n / drops}
                 for d, n in cluster(downs)]
        return {"poses": poses, "unsettled": unsettled}
    finally:
        p.disconnect(physicsClientId=client)


def trimesh_poses(obj):
    import trimesh

    mesh = trimesh.Trimesh(vertices=np.array(obj["vertices"], dtype=float),
                           faces=np.array(obj["faces"], dtype=np.int64), process=True)
    transforms, probabilities = trimesh.poses.compute_stable_poses(
        mesh, center_mass=np.array(obj["cog"], dtype=float))
    out = []
    for t, prob in zip(transforms, probabilities):
        down = np.asarray(t)[:3, :3].T @ np.array([0.0, 0.0, -1.0])
        out.append({"down": down.tolist(), "probability": float(prob)})
    return {"poses": out}


def run_one(args):
    obj, drops, seed = args
    return {"name": obj["name"], "drops": drop(obj, drops, seed),
            "trimesh": trimesh_poses(obj)}


def main():
    import pybullet  # noqa: F401  (prints its build line once, before the workers)
    import trimesh

    with open(sys.argv[1]) as f:
        job = json.load(f)
    jobs = [(o, int(job["drops"]), int(job["seed"])) for o in job["objects"]]
    workers = max(1, int(job.get("workers", 2)))
    with multiprocessing.Pool(workers) as pool:
        results = pool.map(run_one, jobs, chunksize=1)
    out = {"pybullet": "3.2.7", "trimesh": trimesh.__version__, "objects": results}
    with open(sys.argv[2], "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
