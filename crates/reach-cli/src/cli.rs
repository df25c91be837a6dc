//! The command-line grammar (clap derive) and the help texts.

use clap::{Parser, Subcommand};

use crate::commands::demo::DemoArgs;
use crate::commands::dynamics::DynamicsArgs;
use crate::commands::fk::FkArgs;
use crate::commands::ik::IkArgs;
use crate::commands::jacobian::JacobianArgs;
use crate::commands::robot_show::RobotCommand;
use crate::commands::robots::RobotsArgs;

const ABOUT: &str = "Plan and check robot-manipulator motions: models, forward and inverse kinematics, obstacles, configuration space, stepper drives.";

const LONG_ABOUT: &str = "\
Plan and check robot-manipulator motions: models, forward and inverse kinematics, obstacles, configuration space, stepper drives.

A ROBOT is a preset name (see `reach robots`) or a path to a robot file: reach's TOML \
format (.toml) or URDF (.urdf; choose the chain with --base LINK and --tip LINK).

Joint values are given base to tip, in degrees for revolute joints (radians with --rad) and \
in metres for prismatic joints. Negative values need no `--`: `reach fk ur5 -90 -45.5 0 0 0 0`.

Output is for people by default; --json prints machine-readable JSON whose field names \
carry their units (xyz_m, rpy_deg). Orientation triples are roll-pitch-yaw about fixed axes, \
R = Rz(yaw)·Ry(pitch)·Rx(roll); quaternions are w x y z; 4x4 matrices are row-major.";

const AFTER_HELP: &str = "\
Examples:
  reach robots                              list the preset robots
  reach robot show puma560                  DH table in the file's units
  reach robot show varan4 --json            the model as JSON, SI units
  reach fk puma560 0 0 0 0 0 0              tool pose at q = 0 (degrees)
  reach fk ur5 -90 -45.5 0 0 0 0 --json     negative angles, JSON output
  reach fk panda 0 -0.3 0 -2.2 0 2 0.785 --rad
  reach fk arm.urdf --tip tool0 0 30 -60    a URDF chain
  reach jacobian puma560 0 45 -90 0 30 0    6xn Jacobian, manipulability, rank
  reach dynamics puma560 0 45 -90 0 30 0 --qd 10,0,0,0,0,0
                                            joint torques, gravity load, mass matrix
  reach ik puma560 --xyz 0.5,-0.2,0.3 --rpy 180,0,0 --all
                                            every IK solution with its branch label
  reach ik spbu6 --matrix 1,0,0,0,0,0,1,3,0,-1,0,5,0,0,0,1
                                            the solution closest to home
  reach ik planar3 --xyz 2.4,0.2,0 --scan 0.01 --csv table.csv
                                            seed 000's table of configurations
  reach ik ur5 --xyz 0.4,-0.2,0.3 --rpy 180,0,0 --choose topsis --criteria change,limits,manipulability --weights 0.5,0.3,0.2
                                            rank the IK solutions by several criteria
  reach tasks ur5 visiting examples/tasks_visiting.toml --budget 6
                                            least-energy tour of target points
  reach path planar3 examples/path_planar3_post.toml --from 60,-40,-30 --to 0,-30,-30 --duration 10 --svg path.svg
                                            a collision-free path past an obstacle, drawn
  reach cspace varan4 examples/seed004_ceiling.toml --fix q1=0 --png sections
                                            C-space section images, one per value of q2
  reach demo                                a tour of every preset

Exit status: 0 success, 1 internal error, 2 bad input (arguments, numbers, robot files),
3 no solution / infeasible / not clear (ik, move, plan, path, check: the report is still printed
on stdout). Errors are one line
on stderr.";

/// `reach`: the command line of the reach toolkit.
#[derive(Debug, Parser)]
#[command(
    name = "reach",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_help = AFTER_HELP,
    propagate_version = true,
    subcommand_required = true,
    arg_required_else_help = true
)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the preset robots with their number of joints and a description.
    #[command(after_help = "Examples:\n  reach robots\n  reach robots --json")]
    Robots(RobotsArgs),

    /// Inspect a robot model (`reach robot show ROBOT`).
    #[command(
        subcommand,
        after_help = "Examples:\n  reach robot show puma560\n  reach robot show ./my-arm.toml --json"
    )]
    Robot(RobotCommand),

    /// Forward kinematics: the tool pose for joint values.
    #[command(
        allow_negative_numbers = true,
        long_about = "Forward kinematics: the tool pose in the world frame for the given joint \
            values, as position [m], roll-pitch-yaw [deg], quaternion (w x y z) and 4x4 matrix, \
            plus the origin of every link frame. Joints outside their limits are named (the \
            pose is computed regardless).\n\n\
            --json prints {\"robot\", \"q_deg\" (revolute in deg, prismatic in m), \"q_si\", \
            \"outside_limits\", \"pose\": {\"matrix\", \"xyz_m\", \"rpy_deg\", \"quat_wxyz\"}, \
            \"frames\": [4x4 world pose of each link frame]}.",
        after_help = "Examples:\n  \
            reach fk puma560 0 0 0 0 0 0\n  \
            reach fk ur5 -90 -45.5 0 0 0 0 --json\n  \
            reach fk panda 0 -0.3 0 -2.2 0 2 0.785 --rad\n  \
            reach fk arm.urdf --base base_link --tip tool0 0 30 -60"
    )]
    Fk(FkArgs),

    /// The 6xn geometric Jacobian, manipulability, smallest singular value, condition, rank.
    #[command(
        allow_negative_numbers = true,
        long_about = "The geometric Jacobian of the tool point in the world frame (6xn; rows \
            vx vy vz wx wy wz; one column per joint) and the measures derived from its singular \
            values: Yoshikawa's manipulability (their product), the smallest and largest \
            singular value, the condition number (infinite at a singularity) and the numerical \
            rank.\n\n\
            --json prints {\"robot\", \"q_deg\", \"q_si\", \"rows\", \"jacobian\" (6 rows of n), \
            \"manipulability\", \"sigma_min\", \"sigma_max\", \"condition\" (null when singular), \
            \"rank\", \"max_rank\", \"singular_values\"}.",
        after_help = "Examples:\n  \
            reach jacobian puma560 0 45 -90 0 30 0\n  \
            reach jacobian ur5 0 -90 0 -90 0 0 --json\n  \
            reach jacobian planar3 0.5 -1 -1 --rad"
    )]
    Jacobian(JacobianArgs),

    /// Joint torques (inverse dynamics), the gravity load and the mass matrix at one state.
    #[command(
        allow_negative_numbers = true,
        long_about = "Rigid-body dynamics at one state (recursive Newton–Euler; ideal joints, no \
            friction or rotor inertia; the robot's gravity): the joint torques \
            tau = M(q)·qdd + C(q, qd)·qd + g(q), the gravity load g(q) that holds the arm still, \
            and the joint-space mass matrix M(q). The robot needs mass properties (the puma560 \
            preset, a URDF with <inertial>, a TOML with [joints.inertial]). Rates and \
            accelerations are in the unit of the joint values per second (squared).\n\n\
            --json prints {\"robot\", \"q_deg\", \"q_si\", \"qd_si\", \"qdd_si\", \
            \"outside_limits\", \"gravity_m_s2\", \"tau_si\", \"gravity_tau_si\", \
            \"mass_matrix_si\"} (docs/schemas/dynamics.report.schema.json).",
        after_help = "Examples:\n  \
            reach dynamics puma560 0 45 -90 0 30 0\n  \
            reach dynamics puma560 0,45,-90,0,30,0 --qd 10,0,0,0,0,0 --qdd 0,50,0,0,0,0 --json\n  \
            reach dynamics examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf --tip tool0 0 -90 90 0 0 0"
    )]
    Dynamics(DynamicsArgs),

    /// Inverse kinematics: every solution for a tool pose, or the one closest to --from.
    #[command(
        long_about = "Inverse kinematics: the joint values that put the tool at a pose (--xyz with \
            --rpy, or --matrix) or a position (--xyz alone). The solver is detected from the \
            robot's structure (a closed form where one fits, else numeric) or named with \
            --solver. Every solution is verified by forward kinematics and labelled with its \
            branch; without --all the one within limits closest to --from (default: home; \
            least Σ wᵢ·|qᵢ − fromᵢ|, joint weights --joint-weights) is printed.\n\n\
            --choose topsis|vikor|weighted-sum|pareto ranks the solutions within limits by \
            --criteria (change = Σ wᵢ·|qᵢ − fromᵢ| [rad] less is better, limits = smallest \
            normalised distance to a joint limit, manipulability, sigma_min, stiffness = \
            σmin/σmax of the position Jacobian: more is better; accuracy = σmax of the position \
            Jacobian × 0.01° [m]: less is better; \
            default change,limits,manipulability) with --weights, one per criterion (default \
            equal), and prints the ranking table: raw and normalised value per criterion, the \
            score (TOPSIS closeness, VIKOR Q, weighted sum) and whether the solution is \
            Pareto-optimal; rank 1 is chosen. --weights always means criterion weights and \
            needs --choose; joint weights are --joint-weights. See docs/choosing.md.\n\n\
            Units: metres, degrees (prismatic joints in metres); rpy is R = Rz(yaw)·Ry(pitch)·Rx(roll) \
            (radians with --rad); --quat is w,x,y,z; --matrix is 16 numbers row-major, last row 0 0 0 1. \
            Comma lists may start with a minus.\n\n\
            --json prints the report (docs/schemas/ik.report.schema.json; with --scan \
            ik_scan.report.schema.json): {\"robot\", \"solver\", \"status\" (ok, unreachable, singular, \
            outside_limits, orientation_unreachable, no_convergence), \"reason\", \"solutions\": \
            [{\"q_deg\", \"branch\", \"position_error_m\", \"orientation_error_rad\", \
            \"within_limits\", \"violations\", \"singular\"}], \"chosen\", with --choose \"ranking\": \
            {\"method\", \"criteria\": [{\"name\", \"unit\", \"direction\", \"weight\"}], \"score\", \
            \"ranked\": [{\"solution\", \"rank\", \"score\", \"values\", \"normalised\", \"pareto_optimal\"}], vikor only \"vikor\": \
            {\"dq\", \"acceptable_advantage\", \"acceptable_stability\", \"compromise\"}}}. A status other than \
            ok prints the report, one line on stderr, and exits with status 3.\n\n\
            --scan DEG (planar arm of seed 000, position target): the thesis's table of \
            configurations, alpha from alpha_min to 180 deg in steps of DEG, and the row with the \
            least S = |α − α0| + |β − β0| + |γ − γ0| from --from; --csv FILE writes every row \
            (alpha_deg, beta_deg, gamma_deg, q1_deg, q2_deg, q3_deg, S_deg, within_limits, chosen).",
        after_help = "Examples:\n  \
            reach ik puma560 --xyz 0.5,-0.2,0.3 --rpy 180,0,0 --all\n  \
            reach ik ur5 --matrix -1,0,0,0.4,0,1,0,-0.2,0,0,-1,0.3,0,0,0,1 --json\n  \
            reach ik spbu6 --matrix 1,0,0,0,0,0,1,3,0,-1,0,5,0,0,0,1\n  \
            reach ik ur5 --matrix -1,0,0,0.4,0,1,0,-0.2,0,0,-1,0.3,0,0,0,1 --from 0,-90,90,-90,-90,0 --choose topsis --criteria change,limits,manipulability,sigma_min --weights 0.25,0.25,0.25,0.25\n  \
            reach ik puma560 --xyz 0.5,-0.2,0.3 --rpy 180,0,0 --choose vikor --joint-weights 1,1,1,0.2,0.2,0.2\n  \
            reach ik welder6r --xyz 0.05,0.74,0.07 --rpy 0,-41.8685,-50.1944 --from 105,-33,43,-170,-155,138\n  \
            reach ik planar3 --xyz 2,1,0 --free-angle -30 --all\n  \
            reach ik planar3 --xyz 2.4,0.2,0 --scan 0.01 --from 60,-40,-30 --csv table.csv"
    )]
    Ik(Box<IkArgs>),

    /// A short tour: forward kinematics of every preset at its home pose.
    #[command(after_help = "Example:\n  reach demo")]
    Demo(DemoArgs),

    /// Stepper step schedules from a motion file or a point-to-point move: summary, CSV, JSON,
    /// G-code, coil tables or step/direction events.
    #[command(
        long_about = "Stepper step schedules. Each joint's drive data ([joints.drive] in the \
            robot file: steps per revolution, microstepping, gear ratio, direction, maximum step \
            rate and acceleration, wiring); a joint without it gets the default simulated motor \
            that `reach serve` uses (listed under `simulated drives` in the summary). The input is a motion file (JSON {\"samples\": [{\"t_s\", \
            \"q_deg\"}]}) or a point-to-point move (--from/--to, optional --duration), which is \
            synchronised so that all joints start and stop together (seed 000). The schedule is \
            integrated back into joint angles and compared with the plan.\n\n\
            Exit status 3 when the motion exceeds a motor's rate or acceleration limit (the message \
            names the joint, the time and a slower duration that works).",
        after_help = "Examples:\n  \
            reach drive planar3 --from 0,0,0 --to 3.6,-14.4,-7.2\n  \
            reach drive planar3 --from 0,0,0 --to 90,-45,-30 --format gcode -o move.gcode\n  \
            reach drive log-loader --from 0,0,0 --to 90,45,-30 --duration 5 --format csv\n  \
            reach drive planar3 motion.json --format coils\n  \
            reach drive planar3 examples/drive_planar3.toml --format gcode -o cycle.gcode"
    )]
    Drive(crate::commands::drive::DriveArgs),

    /// Collisions and clearances of one configuration in a scene.
    #[command(
        allow_negative_numbers = true,
        long_about = "Collisions and clearances of one configuration: every link of the robot's \
            collision body (its solids: URDF <collision>, a TOML file's [[bodies]], the presets' \
            capsules; without a body, the segment between joint frames with the file's radius) \
            against every obstacle of SCENE, every pair of non-adjacent links not exempt (SRDF, \
            disabled_collisions, the scene's allowed list), and the tool point against the scene's tool zone. Obstacles are \
            closed sets unless the scene says touching = \"open\" (tolerance 1 nm).\n\n\
            --json prints {\"verdict\", \"links\": [{\"link\", \"obstacle\", \"clearance_m\", \
            \"colliding\"}], \"self_pairs\", \"tool_zone\", \"min_obstacle_clearance_m\", \
            \"min_self_clearance_m\"}.\n\n\
            The first line is the verdict of the whole check: with --to or --motion, `clear` or \
            `NOT clear` with the start's verdict and the swept check's. Exit status 0 when the \
            configuration is free and its motion (--to, --motion) proven clear; 3 (after the \
            report, the verdict as one line on stderr) for a collision, a tool outside its zone or \
            a motion not proven clear; 2 for bad input.",
        after_help = "Examples:\n  \
            reach check varan4 examples/seed004_ceiling.toml 0 0 90 0\n  \
            reach check varan4 examples/seed004_two_planes.toml 0 30 -45 10 --json"
    )]
    Check(crate::commands::check::CheckArgs),

    /// Seed 000: plan the planar arm's move past point obstacles (detour on the L/7 circle).
    #[command(
        long_about = "Seed 000's obstacle test and detour for the planar three-link arm: the \
            swept areas of the links between the start and target poses are tested for each \
            point obstacle (robust, orientation-free test; --literal-test for the thesis's \
            printed one); a blocked move goes through two waypoints on a circle of radius L/7 \
            around the obstacle (perpendicular construction; --printed-waypoints for Table 6), \
            each leg with the minimum-change IK and re-checked. Exit status 3 (after the report) \
            when the target is unreachable or no detour exists.\n\n\
            --json prints {\"outcome\", \"blocked\", \"start_deg\", \"waypoints_m\", \
            \"configurations_deg\", \"leg_s_deg\", \"min_clearance_m\"}.\n\n\
            --choose topsis|vikor|weighted-sum plans both sides of the obstacle (the thesis's \
            base side and the far side) and ranks those that succeed by --criteria s (Σ S of the \
            legs [rad], less), clearance [m] (more), path_length (gripper polyline [m], less) \
            with --weights; a single feasible side is reported as the only candidate. JSON adds \
            \"criteria\" and \"sides\": [{\"side\", \"outcome\", \"values\", \"score\", \"chosen\"}].",
        after_help = "Examples:\n  \
            reach avoid planar3 --from 60,-40,-30 --to-xy 2.4,0.2 --obstacle 2.0,0.7\n  \
            reach avoid planar3 --from-xy 2.4245,1.0344 --to-xy 2.4,0.2 --obstacle 2.0,0.7 --json\n  \
            reach avoid planar3 --from 60,-40,-30 --to-xy 2.4,0.2 --obstacle 2.0,0.7 --choose topsis\n  \
            reach avoid planar3 --from 60,-40,-30 --to-xy 2.4,0.2 --sensor 0.5,-0.5,43.66,1.920937 --sensor 3,-0.5,129.81,1.56205"
    )]
    Avoid(crate::commands::avoid::AvoidArgs),

    /// Seed 000: locate an obstacle from two or more ultrasonic range readings.
    #[command(
        long_about = "Locates a point obstacle in the robot's x–y plane from range readings of two \
            or more sensors at known poses (--sensor X,Y,DIR_DEG,RANGE[,CONE_DEG]: position [m], \
            beam direction [deg from +x], measured range [m], full beam angle [deg, default 30]; \
            --sigma: the readings' standard deviation [m], default 0.01). Weighted least squares \
            (Levenberg–Marquardt from every closed-form trilateration point); the beam cones \
            choose between the two intersections of two range circles. The uncertainty radius \
            holds the obstacle with 99.73 % probability (the 1-D 3σ probability; covariance of \
            the fit). \"ambiguous\" when the geometry cannot separate solutions: another \
            position fits inside the cones (\"alternatives\") or the sensors are nearly in line \
            with the obstacle (\"ill_conditioned\"). `reach avoid --sensor …` detours around the \
            sensed obstacle grown by its uncertainty radius.\n\n\
            --json prints {\"obstacle_m\": [x, y], \"uncertainty_m\", \"confidence\", \
            \"residual_m\", \"residuals_m\", \"ambiguous\", \"ambiguity\", \"alternatives_m\", \
            \"covariance_m2\"}.",
        after_help = "Examples:\n  \
            reach sense planar3 --sensor 0.5,-0.5,43.66,1.920937 --sensor 3,-0.5,129.81,1.56205\n  \
            reach sense planar3 --sensor 0,0,0,0.538516,60 --sensor 1,0,180,0.538516,60 --json"
    )]
    Sense(crate::commands::sense::SenseArgs),

    /// Seed 004: classify a joint grid (limits, tool zone, self-collision, obstacles).
    #[command(
        long_about = "Enumerates a joint grid (both limits included; --fix qI=VALUE holds a \
            joint) and classifies every node, in this order: outside the joint limits, tool \
            outside the scene's tool zone, self-collision, obstacle collision, allowed.\n\n\
            --json prints {\"nodes\", \"allowed\", \"outside_limits\", \"outside_zone\", \
            \"self_collision\", \"obstacle_collision\", \"sections\": counts per value of the \
            first swept joint}.",
        after_help = "Examples:\n  \
            reach cspace varan4 examples/seed004_ceiling.toml --fix q1=0\n  \
            reach cspace varan4 examples/seed004_free.toml --fix q1=0 --step 1 --json"
    )]
    Cspace(crate::commands::cspace::CspaceArgs),

    /// One motion between two joint vectors or two tool poses, in joint or tool space:
    /// samples (t, q, q̇, tool pose), intervals, events (K1–K14), J1, J2, feasibility.
    #[command(
        long_about = "One motion between two joint vectors (--from/--to, degrees or radians with \
            --rad) or two tool poses (--from-xyz with --from-rpy or --from-quat, or --from-matrix; \
            the same with --to-; IK at both \
            ends, the solution with the least weighted joint change). --space joint interpolates \
            q(t) = q0 + λ(τ)(q1 − q0); --space tool moves the tool point on a straight line and \
            turns it about one fixed axis, tracked through IK with branch continuity (intervals \
            between singular positions, events K1–K14). J1 = Σ wᵢ|Δqᵢ|, J2 = Σ wᵢ·(total \
            variation of qᵢ), joint weights --joint-weights. energy_j = ∫ Σ|τᵢ·q̇ᵢ| dt in joules \
            (Newton–Euler torques) when the robot file gives link masses (puma560, ur5), else null with \
            the reason in energy_note.\n\n\
            --choose METHOD --criteria C1,.. [--weights w1,..] (tool space): the configuration \
            of each interval is ranked by motion criteria, as a task file's [choose] \
            (docs/choosing.md); the default is kept when none satisfies them (K14).\n\n\
            Exit status 3 when the motion breaks a joint range or speed limit (the report is \
            printed, the reason goes to stderr); 2 for bad input.",
        after_help = "Examples:\n  \
            reach move spbu6 --from 0,0,0,0,0,0 --to 90,0,0,90,0,0 --duration 10 --dt 0.1\n  \
            reach move spbu6 --from 0,0,0,0,0,0 --to 90,0,0,90,0,0 --space tool --duration 10 --json\n  \
            reach move ur5 --from 0,-90,90,0,90,0 --to 45,-60,60,0,90,0 --profile quintic --duration 2 --csv m.csv\n  \
            reach move ur5 --from-xyz 0.4,-0.2,0.3 --from-rpy 180,0,0 --to-xyz 0.4,0.2,0.3 --to-rpy 180,0,0 --space tool --duration 4 --dt 0.1 --choose topsis --criteria limits,manipulability"
    )]
    Move(Box<crate::commands::move_cmd::MoveArgs>),

    /// Run the motions of a task file (docs/task-format.md) and compare them.
    #[command(after_help = "Examples:\n  \
            reach plan examples/seed001_tool_vs_joint.toml\n  \
            reach plan examples/seed003_welding.toml --json")]
    Plan(crate::commands::plan::PlanArgs),

    /// Seed 001's planning tasks: order pick-and-place trips (collection) or target points
    /// (visiting) by least energy J1, and the most that fit a time budget.
    #[command(
        long_about = "Seed 001's planning tasks on the energy functional J1 = Σ wᵢ·|Δqᵢ|. Every point \
            of the task file gets one configuration (IK within limits closest to the start or \
            container configuration, or the rank-1 solution of the file's [choose] ranking). \
            visiting: one open tour from the start through every reachable target, exact \
            (Held–Karp) up to 12 targets, nearest neighbour + 2-opt beyond. collection: trips \
            container -> object -> container; their total J1 does not depend on the order. \
            Unreachable points are reported and skipped. Durations: synchronised point-to-point \
            moves within the joint speed limits (robot file or the task's max_velocity) with the \
            task's profile; --budget S also reports the largest number of points that fit in S \
            seconds. Task format: docs/task-format.md.\n\n\
            --json prints {\"robot\", \"task\", \"solver\", \"choice\", \"node0_q_deg\", \"points\": \
            [{\"index\", \"xyz_m\", \"rpy_deg\", \"q_deg\", \"branch\", \"reason\"}], \"unreachable\", \
            \"plan\": {\"order\", \"legs\": [{\"point\", \"j1_rad\", \"duration_s\"}], \"total_j1_rad\", \
            \"total_duration_s\", \"exact\", \"method\"}, \"budget_s\", \"within_budget\"}.\n\n\
            Exit status 2 for bad input, including a task whose points are all unreachable; 3 \
            when the container is unreachable.",
        after_help = "Examples:\n  \
            reach tasks ur5 visiting examples/tasks_visiting.toml\n  \
            reach tasks ur5 visiting examples/tasks_visiting.toml --budget 6 --json\n  \
            reach tasks ur5 collection examples/tasks_collection.toml --budget 8\n  \
            reach tasks ur5 visiting examples/tasks_visiting.toml --budget 6 --svg tour.svg"
    )]
    Tasks(crate::commands::tasks::TasksArgs),
    /// A collision-free joint-space path through a scene (RRT-Connect), timed and re-checked.
    #[command(
        long_about = "Plans a collision-free joint-space path from --from to --to (degrees) or to a \
            tool pose (--to-xyz with --to-rpy or --to-quat, or --to-matrix; every feasible, \
            collision-free IK solution is a goal) with RRT-Connect and random shortcutting \
            (seeded: the same --seed gives the same path unless the --time-budget wall-time budget \
            cuts the search). The waypoints are then timed with cycloidal segments that stop at \
            each waypoint (fastest within the speed limits, or --duration shared by length), \
            sampled, and every sample is re-checked for collisions: the report gives the \
            waypoints, the planning statistics (iterations, time, joint-space path length before \
            and after shortcutting), the duration and the smallest clearance.\n\n\
            Exit status 3 (after the report) when no path is found: budget exhausted, start or \
            goal in collision, no IK solution for the goal pose.",
        after_help = "Examples:\n  \
            reach path planar3 examples/path_planar3_post.toml --from 60,-40,-30 --to 0,-30,-30 --duration 10\n  \
            reach path planar3 examples/path_planar3_post.toml --from 60,-40,-30 --to 0,-30,-30 --duration 10 --json --svg path.svg"
    )]
    Path(Box<crate::commands::path::PathArgs>),

    /// Seed 004: a motion to a goal that keeps a safe distance from the obstacles.
    #[command(
        long_about = "Synthesises joint increments from --from to --to (degrees) or to a tool pose \
            (--to-xyz alone: a position goal, redundant arms such as varan4 and planar3 resolve \
            the redundancy in the null space of the task Jacobian) that keep --safe-distance \
            metres from every obstacle of the scene, the distance acting as a barrier. Every \
            increment is proven clear over its whole motion by the swept check, not only at the \
            samples. When the goal direction and the barrier oppose (a deadlock) the report says \
            so and the planner takes over from there (unless --no-handover). --fast-region fits \
            seed 004's R-function region first and drops candidate increments clearly outside \
            it before the exact check.\n\n\
            Exit status 3 (after the report) when the goal is not reached: deadlock (even when \
            the planner found a path) or unreachable goal.",
        after_help = "Examples:\n  \
            reach approach varan4 examples/seed004_ceiling.toml --from 0,30,0,0 --to-xyz 1.5,0,0.6\n  \
            reach approach varan4 examples/seed004_ceiling.toml --from 0,30,0,0 --to-xyz 1.0643,0,1.1296 --json"
    )]
    Approach(Box<crate::commands::approach::ApproachArgs>),

    /// The time-optimal motion through a path's waypoints under the joints' velocity and
    /// acceleration limits, proven within them between samples.
    #[command(
        long_about = "Times a joint path as fast as the joints' velocity and acceleration limits \
            allow (TOPP-RA, the reachability method of Pham & Pham 2018), starting and ending at \
            rest. The limits are the robot's max_velocity and max_acceleration (TOML fields, or a \
            MoveIt joint_limits.yaml with --joint-limits for a URDF), times \
            --max-velocity-scale / --max-acceleration-scale. The waypoints are joined by a cubic \
            spline (not-a-knot at uniform parameter, the path toppra builds; no stop at the \
            waypoints) or by straight segments (--interpolation linear: rests at every \
            waypoint). A spline that leaves a joint's position limits between waypoints is \
            refused, naming the joint and the segment.\n\n\
            Within limits everywhere, not only at samples: the largest speed and acceleration \
            of every joint between the parameterisation's grid points are computed exactly, \
            the motion is slowed uniformly by the factor that brings them within the limits, \
            and the report gives each joint's exact worst ratio to its limits.\n\n\
            PATH is a CSV (one joint vector per row: degrees, or radians with --rad; prismatic \
            joints in metres), or the JSON of `reach path --json` (waypoints_deg), \
            `reach approach --json` (motion_deg) or `reach move --json` (samples); `-` reads \
            standard input.\n\n\
            --json prints the report (docs/schemas/retime.report.schema.json, SI units): \
            {\"robot\", \"interpolation\", \"waypoints\", \"duration_s\", \"grid_points\", \
            \"slowdown\", \"velocity_limits\", \"acceleration_limits\", \"worst_velocity_ratio\", \
            \"worst_acceleration_ratio\", \"samples\": [{\"t_s\", \"q\", \"qd\", \"qdd\"}]}. \
            --ros FILE writes the motion as the ROS 2 message trajectory_msgs/JointTrajectory \
            (docs/schemas/joint_trajectory.schema.json; YAML for .yaml/.yml, JSON for .json).",
        after_help = "Examples:\n  \
            reach retime panda examples/panda_waypoints.csv\n  \
            reach retime panda examples/panda_waypoints.csv --max-velocity-scale 0.5 --csv timed.csv\n  \
            reach retime panda examples/panda_waypoints.csv --ros timed.yaml\n  \
            reach path ur5 examples/ur5_ball.toml --from 90,-90,90,-90,-90,0 --to -90,-60,60,-90,-90,0 --json | reach retime ur5 - --json"
    )]
    Retime(crate::commands::retime::RetimeArgs),

    /// The control service: an HTTP + WebSocket API that queues jobs, plays them on simulated
    /// stepper drives and keeps the arm's state in a database (see the README's "The control
    /// service").
    #[command(
        long_about = "The control service: an HTTP + WebSocket API (GET /openapi.json describes it) \
            that plans each submitted job with the library, refuses infeasible ones, plays the \
            others on simulated stepper drives in real time (or --speed times faster) and commits \
            every joint's step counter at least every 50 ms of motion to an SQLite database in the \
            state directory. After a crash, a restart shows the last committed position, marks the \
            running job `interrupted` and keeps the queue, paused until POST /resume.\n\n\
            It listens on loopback by default; on any other address every request needs the \
            token in STATE/token (Authorization: Bearer TOKEN). Ctrl-C ends it.",
        after_help = "Examples:\n  \
            reach serve ur5\n  \
            reach serve planar3 --state /var/lib/reach --speed 10\n  \
            reach serve planar3 --scene examples/path_planar3_post.toml --listen 0.0.0.0:7878"
    )]
    Serve(crate::commands::serve::ServeArgs),

    /// A client of a running `reach serve`: submit jobs, show their status, watch the arm,
    /// stop and resume.
    #[command(after_help = "Examples:\n  \
            reach job submit '{\"kind\": \"move\", \"to_deg\": [90, -60, 60, 30, 60, 90], \"duration_s\": 6}' --wait\n  \
            reach job submit job.json --url http://10.0.0.5:7878 --token $(cat reach-state/token)\n  \
            reach job status 3\n  \
            reach job watch --count 100\n  \
            reach job stop\n  \
            reach job resume")]
    Job(crate::commands::job::JobArgs),

    /// The robot in 3-D: one self-contained HTML file (motion playback, scene, IK ghosts).
    #[command(
        allow_negative_numbers = true,
        long_about = "Writes one self-contained HTML file (-o) that shows the robot in 3-D in a \
            browser, offline: the arm as capsules between its frames with joint axes and frames, \
            at Q (default home), or playing a motion (--motion, a `reach move --json` report; \
            --plan, a task file planned for ROBOT) with a time slider, play/pause, the events \
            (K-codes, infeasible intervals) marked on the timeline and a joint plot; the tool \
            path; the obstacles and tool zone of --scene; and with --ik-xyz (and --ik-rpy or \
            --ik-quat) every IK solution of that target as a ghost arm. A URDF robot is drawn \
            with its visual meshes (STL, Collada), inlined: package://NAME/.. resolves to the \
            directory NAME above the URDF file, other addresses to the file's directory; a \
            missing mesh is an error (--no-meshes: capsules). --cspace I,J adds a C-space \
            section of joints I and J over --scene (the other joints at the first state's \
            values) with the motion's path in it. At most 2000 states are shipped (a longer \
            motion is thinned evenly). See docs/viewer.md.",
        after_help = "Examples:\n  \
            reach view ur5 0 -90 90 0 90 0 -o ur5.html\n  \
            reach view ur5 --ik-xyz 0.4,0.2,0.3 --ik-rpy 180,0,0 -o ik.html\n  \
            reach view welder6r --plan examples/seed003_welding.toml -o weld.html\n  \
            reach view varan4 0 30 -45 10 --scene examples/seed004_two_planes.toml -o zones.html\n  \
            reach view varan4 0 30 0 0 --scene examples/seed004_ceiling.toml --cspace 2,3 -o cspace.html\n  \
            reach view examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf --tip tool0 -o kr16.html"
    )]
    View(crate::commands::view::ViewArgs),
}
