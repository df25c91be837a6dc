//! The command-line grammar (clap derive) and the help texts.

use clap::{Parser, Subcommand};

use crate::commands::demo::DemoArgs;
use crate::commands::fk::FkArgs;
use crate::commands::jacobian::JacobianArgs;
use crate::commands::robot_show::RobotCommand;
use crate::commands::robots::RobotsArgs;

const ABOUT: &str = "Robot manipulator kinematics: robots, forward kinematics, Jacobians.";

const LONG_ABOUT: &str = "\
Robot manipulator kinematics: robots, forward kinematics, Jacobians.

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
  reach demo                                a tour of every preset

Exit status: 0 success, 1 internal error, 2 bad input (arguments, numbers, robot files),
3 no solution / infeasible (reserved). Errors are one line on stderr.";

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

    /// A short tour: forward kinematics of every preset at its home pose.
    #[command(after_help = "Example:\n  reach demo")]
    Demo(DemoArgs),
}
