"""The controller template (sim/controllers/template.py) filled in by a second student, in a style
of their own (tests/app/grading/test_similarity.py: two honest fills of the template are not flagged).

cooperative_lifting.py — the lab's exercise: implement the Single Point (SP) method.

Run it:    hri-lab serve --controller cooperative_lifting.py      (the live lab, http://127.0.0.1:8000/)
           hri-lab experiment --controller cooperative_lifting.py  (the nine trials, headless)
Grade it:  hri-lab grade cooperative_lifting.py

Conventions (as franka_ros): wrench_ee = F_ext = [fx, fy, fz, mx, my, mz] is the wrench the ROBOT
applies to the box, at the flange origin, in the flange (EE) frame; the plate's normal n is the
EE z axis, its centre p_c = [0, 0, params.plate_offset]. Pressing the box gives f_n = n . f > 0.
Return the EE twist [vx, vy, vz, wx, wy, wz] in the BASE frame (m/s, rad/s).
As it is, this file runs and commands zero twist: the robot does not move.
"""

import numpy as np  # the handout's tools: np.dot, np.cross, np.linalg.norm, np.clip, np.hstack


class CooperativeLifting:
    def __init__(self):
        self.reset()

    def reset(self):
        """Called when the simulation (re)starts and after an error recovery."""
        self.twist_base = np.zeros(6)  # the last command (step 6's rate limit needs it)
        self.wrench_filtered = None  # step 0's low-passed F_ext

    # --- the services' handlers -------------------------------------------------------------
    def start(self, params, force):
        """start_cooperative_lifting: f_n_min = force, f_n_max = force + params.f_n_band, and start."""
        params.running, params.f_n_min = True, float(force)
        return f"Cooperative Lifting started with f_n_min = {force:g} N."

    def stop(self, params):
        """stop_cooperative_lifting: f_n_min = 0 and stop (zero twist)."""
        params.running, params.f_n_min = False, 0.0
        return "Cooperative Lifting was stopped! Force limit f_n_min reset to 0 N."

    # --- the controller -----------------------------------------------------------------------
    def step(self, wrench_ee, transform_ee_to_base, params, dt):
        """One control period (dt = 1 ms): F_ext in, EE twist in the base frame out."""
        # TODO step 0: low-pass F_ext against the sensor noise (0.5 N), first order at params.filter_hz:
        #   a = dt / (1 / (2 pi filter_hz) + dt);  w_f = w_f + a (wrench_ee - w_f)   (w_f = wrench_ee at the first step)
        #   Without it the noise makes the twist jump at every step and the robot stops on a reflex.
        measured = np.array(wrench_ee, dtype=float)
        if self.wrench_filtered is None:
            self.wrench_filtered = measured
        tau = 1.0 / (2.0 * np.pi * params.filter_hz)
        self.wrench_filtered = self.wrench_filtered + (measured - self.wrench_filtered) * (dt / (tau + dt))
        wrench = self.wrench_filtered
        if not params.running:
            return np.zeros(6)
        f, m = wrench[:3], wrench[3:]
        rotation = transform_ee_to_base[:3, :3]  # EE -> base

        # TODO step 1: decompose the wrench at the plate
        #   n = [0, 0, 1];  f_n = n . f;  f_t = f - f_n n;  m_c = m - p_c x f
        normal = np.array([0.0, 0.0, 1.0])
        push = float(f @ normal)
        shear = f - push * normal
        moment = m - np.cross(np.array([0.0, 0.0, params.plate_offset]), f)
        touching = push >= params.f_contact

        # TODO step 2: normal regulation in the band [params.f_n_min, params.f_n_max]
        #   below -> move along +n (press); above -> along -n (release); inside -> no normal motion
        def toward_band(target):
            return params.k_n * (target - push)

        speed_n = toward_band(params.f_n_min) if push < params.f_n_min else 0.0
        if push > params.f_n_max:
            speed_n = toward_band(params.f_n_max)

        # TODO step 3: tangential following with the friction cone (params.mu, params.alpha)
        #   |f_t| <= alpha mu f_n -> no tangential motion;  beyond: e_t = f_t - alpha mu f_n f_t/|f_t|,
        #   v_t = -params.k_t e_t  (F_ext is what the robot applies: move AGAINST f_t), and press harder
        cone = params.alpha * params.mu * max(push, 0.0)
        shear_size = float(np.sqrt(shear @ shear))
        slide = np.zeros(3)
        if touching and shear_size > cone:
            excess = shear * (1.0 - cone / shear_size)
            slide = excess * -params.k_t
            if push < params.f_n_max:
                speed_n = max(speed_n, toward_band(params.f_n_max))

        # TODO step 4: comply with the moment at the plate centre: w = -params.k_w m_c (with a deadband)
        turn = np.zeros(3)
        moment_size = float(np.sqrt(moment @ moment))
        if touching and moment_size > params.moment_deadband:
            turn = moment * (params.moment_deadband / moment_size - 1.0) * params.k_w

        # TODO step 5a: twist_ee = [v, w] with v = v_t + v_n n, saturated at params.v_max / params.w_max
        # TODO step 5b: rotate it to the base frame: twist_base = [R v, R w]
        # TODO step 6: limit the rate: the command may change by at most params.a_max * dt (linear) and
        #   params.dw_max * dt (angular) per step, starting from self.twist_base (the robot refuses
        #   jumps above 13 m/s^2: a jump is a reflex)
        def capped(vector, most):
            size = float(np.sqrt(vector @ vector))
            return vector if size <= most else vector * (most / size)

        linear = capped(slide + speed_n * normal, params.v_max)
        angular = capped(turn, params.w_max)
        wanted = np.concatenate([rotation.dot(linear), rotation.dot(angular)])
        change = wanted - self.twist_base
        change[:3] = capped(change[:3], params.a_max * dt)
        change[3:] = capped(change[3:], params.dw_max * dt)
        twist_base = self.twist_base + change

        self.twist_base = twist_base
        return twist_base
