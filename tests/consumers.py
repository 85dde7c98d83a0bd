"""The exported URDF read by the other tools: each one's joint-space mass matrix and damping.

Pinocchio's own parser, MuJoCo (mj_fullM), pybullet (calculateMassMatrix) and yourdfpy (the sum
of the links' Jacobian terms, walked from its parsed joints): independent readings of one file.
"""

import numpy as np
import pinocchio as pin
import pytest


def rot(axis: np.ndarray, angle: float) -> np.ndarray:
    a = axis / np.linalg.norm(axis)
    S = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * S + (1 - np.cos(angle)) * S @ S


def yourdfpy_mass_and_damping(path, poses):
    """M = sum_i m_i Jv_i^T Jv_i + Jw_i^T R_i I_i R_i^T Jw_i over yourdfpy's parsed links, with
    the kinematics walked from its joint origins and axes."""
    yourdfpy = pytest.importorskip("yourdfpy")
    robot = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
    names = robot.actuated_joint_names
    joints = list(robot.joint_map.values())
    (base,) = set(robot.link_map) - {j.child for j in joints}
    n = len(names)
    Ms = []
    for q in poses:
        qmap = dict(zip(names, q, strict=True))
        frames = {base: (np.eye(4), [])}  # link -> (world pose, [(dof, point, axis)])
        pending = list(joints)
        while pending:
            joint = next(j for j in pending if j.parent in frames)
            pending.remove(joint)
            T, chain = frames[joint.parent]
            T = T @ joint.origin
            chain = list(chain)
            if joint.type == "revolute":
                axis = np.asarray(joint.axis, dtype=float)
                chain.append((names.index(joint.name), T[:3, 3].copy(), T[:3, :3] @ axis))
                R = np.eye(4)
                R[:3, :3] = rot(axis, qmap[joint.name])
                T = T @ R
            frames[joint.child] = (T, chain)
        M = np.zeros((n, n))
        for name, link in robot.link_map.items():
            if link.inertial is None:
                assert name == base
                continue
            T, chain = frames[name]
            Tc = T @ link.inertial.origin
            c, R = Tc[:3, 3], Tc[:3, :3]
            Jv, Jw = np.zeros((3, n)), np.zeros((3, n))
            for dof, point, axis in chain:
                Jv[:, dof] = np.cross(axis, c - point)
                Jw[:, dof] = axis
            M += link.inertial.mass * Jv.T @ Jv + Jw.T @ R @ link.inertial.inertia @ R.T @ Jw
        Ms.append(M)
    # yourdfpy keeps the damping attribute as the file's string
    damping = np.array([float(robot.joint_map[j].dynamics.damping) for j in names])
    return Ms, damping


def pybullet_mass_and_damping(path, poses):
    p = pytest.importorskip("pybullet")
    cid = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(path), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                          physicsClientId=cid)
        info = [p.getJointInfo(body, j, physicsClientId=cid)
                for j in range(p.getNumJoints(body, physicsClientId=cid))]
        dofs = [i for i in info if i[2] == p.JOINT_REVOLUTE]
        masses = {i[12].decode(): p.getDynamicsInfo(body, i[0], physicsClientId=cid)[0]
                  for i in info}
        Ms = [np.array(p.calculateMassMatrix(body, [float(v) for v in q], physicsClientId=cid))
              for q in poses]
        return Ms, np.array([i[6] for i in dofs]), masses
    finally:
        p.disconnect(cid)


def mujoco_mass_and_damping(path, poses):
    mujoco = pytest.importorskip("mujoco")
    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    assert m.nv == 4 and tuple(m.opt.gravity) == (0.0, 0.0, -9.81)
    Ms = []
    for q in poses:
        d.qpos[:] = q
        mujoco.mj_forward(m, d)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        Ms.append(M)
    return Ms, np.array(m.dof_damping)


def pinocchio_mass_and_damping(path, poses):
    pm = pin.buildModelFromUrdf(str(path))
    pm.gravity = pin.Motion.Zero()
    data = pm.createData()
    Ms = []
    for q in poses:
        M = pin.crba(pm, data, q)
        Ms.append(np.triu(M) + np.triu(M, 1).T)
    return Ms, np.array(pm.damping)


def consumer_joint_names(path):
    """The moving joints in the order of each consumer's coordinates: pybullet's (revolute
    joints by joint index; the fixed clamp and tip joints hold none) and yourdfpy's."""
    p = pytest.importorskip("pybullet")
    yourdfpy = pytest.importorskip("yourdfpy")
    cid = p.connect(p.DIRECT)
    try:
        body = p.loadURDF(str(path), useFixedBase=True, flags=p.URDF_USE_INERTIA_FROM_FILE,
                          physicsClientId=cid)
        info = [p.getJointInfo(body, j, physicsClientId=cid)
                for j in range(p.getNumJoints(body, physicsClientId=cid))]
        bullet = [i[1].decode() for i in info if i[2] == p.JOINT_REVOLUTE]
    finally:
        p.disconnect(cid)
    robot = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
    return bullet, list(robot.actuated_joint_names)


def mujoco_from_spatial_urdf(text, node_axes, n_nodes, folder=None):
    """MuJoCo's model of a spatial chain's URDF, its massless node links fused away.

    MuJoCo's compiler refuses a body that has joints when neither it nor a jointless body
    below it (reached without crossing another jointed body) has mass and principal inertias
    >= mjMINVAL ("mass and inertia of moving bodies must be larger than mjMINVAL",
    mjCModel::CheckBodyMassInertia in src/user/user_model.cc): the rule is on the body and its
    static children, not on the subtree mass. The massless links link_j_y, link_j_z each carry
    a joint and have a jointed child, so the URDF does not compile as it is, and no compiler
    option of the URDF's <mujoco> element makes it: fusestatic fuses jointless bodies only,
    balanceinertia only repairs a violated triangle inequality, and boundmass / boundinertia
    would give those links mass, which would change M. What compiles it unchanged: parse it
    into an MjSpec and, before compiling, turn each node's later bodies into frames of its
    first (MjsBody.to_frame moves a body's joints, children and inertia into its parent, the
    joints appended in order): node j becomes one body with the hinges y, z, x at one point
    and link j's inertia, the MJCF export's structure.
    """
    mujoco = pytest.importorskip("mujoco")
    spec = mujoco.MjSpec.from_string(text)
    if folder is not None:  # the URDF's mesh paths are relative to its folder
        spec.meshdir = str(folder)
    for j in range(1, n_nodes + 1):
        first = spec.body(f"link_{j}_{node_axes[0]}")
        for a in node_axes[1:-1]:
            spec.body(f"link_{j}_{a}").to_frame()
        spec.body(f"link_{j}").to_frame()
        first.name = f"link_{j}"
    return spec.compile()


def mujoco_mass_matrices(m, poses):
    """MuJoCo's mass matrix (mj_fullM after mj_forward) at each pose of qpos."""
    mujoco = pytest.importorskip("mujoco")
    d = mujoco.MjData(m)
    Ms = []
    for q in poses:
        d.qpos[:] = q
        mujoco.mj_forward(m, d)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_fullM(m, d, M)
        Ms.append(M)
    return Ms
