//! The verifier against tampered plans: one valid plan of the paper's eight objects and many
//! copies, each with one thing wrong. Every copy must be rejected: refused as a document, or
//! verified as not executable. A copy that passes is a hole in the verifier.

mod common;

use pushpack::plan::{optimize, Plan, PlanOptions};
use pushpack::verify::verify;
use serde_json::{json, Value};
use std::sync::OnceLock;

fn inst() -> &'static pushpack::instance::Instance {
    static I: OnceLock<pushpack::instance::Instance> = OnceLock::new();
    I.get_or_init(|| common::load("paper/exp2_8objects.toml"))
}

fn valid_plan() -> &'static Value {
    static P: OnceLock<Value> = OnceLock::new();
    P.get_or_init(|| {
        let inst = inst();
        let out = optimize(inst, &PlanOptions::from_instance(inst)).unwrap();
        serde_json::to_value(&out.plan).unwrap()
    })
}

/// Why a tampered copy is rejected, or `None` when the verifier accepts it.
fn rejection(v: &Value) -> Option<String> {
    let plan = match Plan::from_json(&v.to_string(), "tampered.json") {
        Ok(p) => p,
        Err(e) => return Some(format!("refused: {e}")),
    };
    let r = verify(inst(), &plan);
    (!r.is_executable()).then(|| r.to_string())
}

type Mutation = (String, Box<dyn Fn(&mut Value)>);

fn m(name: &str, f: impl Fn(&mut Value) + 'static) -> Mutation {
    (name.to_string(), Box::new(f))
}

fn add(v: &mut Value, by: f64) {
    *v = json!(v.as_f64().unwrap() + by);
}

/// A point of trajectory `t` in the middle of a motion: not at a key pose's time, not an end,
/// and at most one sampling step from both neighbours (not beside a gripper's dwell).
fn inner_point(plan: &Value, t: usize) -> usize {
    let tr = &plan["trajectories"][t];
    let pts = tr["points"].as_array().unwrap();
    let time = |i: usize| pts[i]["t"].as_f64().unwrap();
    let key_times: Vec<f64> = tr["key_poses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| k["t"].as_f64().unwrap())
        .collect();
    let dt = plan["robot"]["timing"]["sample_dt"].as_f64().unwrap();
    (pts.len() / 2..pts.len() - 1)
        .chain(1..pts.len() / 2)
        .find(|&i| {
            key_times.iter().all(|k| (k - time(i)).abs() > 1e-6)
                && time(i) - time(i - 1) <= dt + 1e-9
                && time(i + 1) - time(i) <= dt + 1e-9
        })
        .expect("a trajectory has inner points")
}

fn mutations(plan: &Value) -> Vec<Mutation> {
    let n_actions = plan["actions"].as_array().unwrap().len();
    let n_traj = plan["trajectories"].as_array().unwrap().len();
    let places: Vec<usize> = (0..n_actions)
        .filter(|&k| plan["actions"][k]["kind"] == "place")
        .collect();
    let pushes: Vec<usize> = (0..n_actions)
        .filter(|&k| plan["actions"][k]["kind"] == "push")
        .collect();
    let mut v: Vec<Mutation> = Vec::new();
    // Actions.
    for &k in places.iter().take(3) {
        v.push(m(&format!("action {k}: grasp axis flipped"), move |p| {
            let a = &mut p["actions"][k]["grasp_axis"];
            *a = json!(if a == "x" { "y" } else { "x" });
        }));
        for (d, name) in [(0.01, "1 cm"), (0.05, "5 cm")] {
            v.push(m(
                &format!("action {k}: a key pose moved {name}, cost patched"),
                move |p| {
                    add(&mut p["actions"][k]["key_poses"][1]["position"][0], d);
                    add(&mut p["actions"][k]["cost"], 2.0 * d);
                },
            ));
        }
        v.push(m(&format!("action {k}: the other arm"), move |p| {
            let a = &mut p["actions"][k]["arm"];
            *a = json!(if a == "left" { "right" } else { "left" });
        }));
        v.push(m(&format!("action {k}: release footprint shifted 5 mm"), move |p| {
            add(&mut p["actions"][k]["release"]["x0"], 0.005);
            add(&mut p["actions"][k]["release"]["x1"], 0.005);
        }));
        v.push(m(&format!("action {k}: cost off by 10 cm"), move |p| {
            add(&mut p["actions"][k]["cost"], 0.1)
        }));
    }
    for &k in &pushes {
        v.push(m(&format!("action {k}: push distance +1 cm"), move |p| {
            add(&mut p["actions"][k]["distance"], 0.01)
        }));
        v.push(m(&format!("action {k}: pusher moved 2 cm sideways"), move |p| {
            add(&mut p["actions"][k]["pusher_at"], 0.02)
        }));
        v.push(m(&format!("action {k}: push direction flipped"), move |p| {
            let d = &mut p["actions"][k]["push_dir"];
            *d = json!(if d == "-x" { "-y" } else { "-x" });
        }));
    }
    v.push(m("actions 0 and 1 swapped", |p| {
        p["actions"].as_array_mut().unwrap().swap(0, 1)
    }));
    v.push(m("last action deleted", |p| {
        p["actions"].as_array_mut().unwrap().pop();
    }));
    v.push(m("first action repeated", |p| {
        let a = p["actions"][0].clone();
        p["actions"].as_array_mut().unwrap().push(a);
    }));
    v.push(m("an indirect place made direct", move |p| {
        let k = (0..n_actions).find(|&k| p["actions"][k]["mode"] == "indirect").unwrap();
        p["actions"][k]["mode"] = json!("direct");
    }));
    // Metrics and claims.
    v.push(m("seq_len + 1", |p| add(&mut p["metrics"]["seq_len"], 1.0)));
    v.push(m("travel × 0.9", |p| {
        let t = p["metrics"]["travel"].as_f64().unwrap();
        p["metrics"]["travel"] = json!(0.9 * t);
    }));
    v.push(m("swept area × 0.9", |p| {
        let t = p["metrics"]["swept_area"].as_f64().unwrap();
        p["metrics"]["swept_area"] = json!(0.9 * t);
    }));
    v.push(m("one push fewer counted", |p| add(&mut p["metrics"]["n_push"], -1.0)));
    v.push(m("placement lower bound above the objective", |p| {
        let a = p["placement"]["occupied_area"].as_f64().unwrap();
        p["placement"]["lower_bound"] = json!(1.5 * a);
    }));
    v.push(m("negative placement gap", |p| p["placement"]["gap"] = json!(-0.1)));
    v.push(m("optimal with a gap of 0.5", |p| {
        p["placement"]["gap"] = json!(0.5);
        p["solver"]["placement"]["gap"] = json!(0.5);
    }));
    v.push(m("occupied area understated", |p| {
        let a = p["placement"]["occupied_area"].as_f64().unwrap();
        p["placement"]["occupied_area"] = json!(0.8 * a);
    }));
    v.push(m("contact length overstated", |p| {
        add(&mut p["placement"]["contact_length"], 0.1)
    }));
    v.push(m("a target moved 1 cm", |p| add(&mut p["placements"][0]["x"], 0.01)));
    v.push(m("a target's size changed", |p| {
        add(&mut p["placements"][1]["size_x"], 0.01)
    }));
    v.push(m("run claimed optimal with a heuristic sequence", |p| {
        p["solver"]["sequence"]["status"] = json!("heuristic");
        p["status"] = json!("optimal");
    }));
    v.push(m("sequence claimed optimal though stopped by the time limit", |p| {
        p["solver"]["sequence"]["stopped_by"] = json!("time");
    }));
    v.push(m("sequence bound above the plan", |p| {
        p["solver"]["sequence"]["cost_bound"]["len"] = json!(99);
    }));
    // Trajectories.
    v.push(m("trajectories: []", |p| p["trajectories"] = json!([])));
    v.push(m("a trajectory deleted", |p| {
        p["trajectories"].as_array_mut().unwrap().remove(3);
    }));
    v.push(m("two trajectories swapped", |p| {
        p["trajectories"].as_array_mut().unwrap().swap(0, 1)
    }));
    let with_poses: Vec<usize> = (0..n_traj)
        .filter(|&t| !plan["trajectories"][t]["key_poses"].as_array().unwrap().is_empty())
        .collect();
    let picks = [
        with_poses[0],
        with_poses[with_poses.len() / 2],
        with_poses[with_poses.len() - 1],
    ];
    for t in picks {
        v.push(m(&format!("trajectory {t}: velocities of 1000 rad/s"), move |p| {
            for pt in p["trajectories"][t]["points"].as_array_mut().unwrap() {
                pt["velocities"] = json!(vec![1000.0; 6]);
            }
        }));
        v.push(m(&format!("trajectory {t}: 5 values for 6 joints"), move |p| {
            p["trajectories"][t]["points"][2]["positions"]
                .as_array_mut()
                .unwrap()
                .pop();
        }));
        v.push(m(
            &format!("trajectory {t}: a joint moved 0.05 rad at one point"),
            move |p| add(&mut p["trajectories"][t]["points"][5]["positions"][1], 0.05),
        ));
        v.push(m(
            &format!("trajectory {t}: a joint moved 0.3 rad at one point"),
            move |p| add(&mut p["trajectories"][t]["points"][5]["positions"][1], 0.3),
        ));
        v.push(m(&format!("trajectory {t}: time going backwards"), move |p| {
            let t1 = p["trajectories"][t]["points"][4]["t"].clone();
            p["trajectories"][t]["points"][6]["t"] = t1;
        }));
        v.push(m(&format!("trajectory {t}: a point at t = 1e300"), move |p| {
            p["trajectories"][t]["points"][3]["t"] = json!(1e300);
        }));
        v.push(m(&format!("trajectory {t}: all points 10× faster"), move |p| {
            for pt in p["trajectories"][t]["points"].as_array_mut().unwrap() {
                let x = pt["t"].as_f64().unwrap();
                pt["t"] = json!(x / 10.0);
            }
        }));
        // Timing within the URDF's limits but not within the plan's own (scaled) ones, and
        // recorded velocities that are not those of the positions.
        let i = inner_point(plan, t);
        let vel: Vec<f64> = plan["trajectories"][t]["points"][i]["velocities"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let j = (0..6).min_by(|&a, &b| vel[a].abs().total_cmp(&vel[b].abs())).unwrap();
        assert!(vel[j].abs() + 0.2 < 0.45, "the jump stays below the velocity limit");
        v.push(m(
            &format!("trajectory {t}: a recorded velocity jumps 0.2 rad/s at one point"),
            move |p| add(&mut p["trajectories"][t]["points"][i]["velocities"][j], 0.2),
        ));
        v.push(m(
            &format!("trajectory {t}: a joint moved 5 mrad at one point"),
            move |p| add(&mut p["trajectories"][t]["points"][i]["positions"][j], 0.005),
        ));
        v.push(m(
            &format!("trajectory {t}: 5 % faster, key poses along, velocities as recorded"),
            move |p| {
                let tr = &mut p["trajectories"][t];
                let t0 = tr["t_start"].as_f64().unwrap();
                let faster = |x: &mut Value| *x = json!(t0 + (x.as_f64().unwrap() - t0) / 1.05);
                faster(&mut tr["t_end"]);
                for pt in tr["points"].as_array_mut().unwrap() {
                    faster(&mut pt["t"]);
                }
                for kp in tr["key_poses"].as_array_mut().unwrap() {
                    faster(&mut kp["t"]);
                }
            },
        ));
        v.push(m(&format!("trajectory {t}: the other arm"), move |p| {
            let a = &mut p["trajectories"][t]["arm"];
            *a = json!(if a == "left" { "right" } else { "left" });
        }));
        v.push(m(&format!("trajectory {t}: a joint name changed"), move |p| {
            p["trajectories"][t]["joint_names"][0] = json!("WAIST");
        }));
        v.push(m(
            &format!("trajectory {t}: a key pose's joints off by 0.1 rad"),
            move |p| add(&mut p["trajectories"][t]["key_poses"][0]["joints"][2], 0.1),
        ));
        v.push(m(&format!("trajectory {t}: a gripper opening of 1 m"), move |p| {
            p["trajectories"][t]["key_poses"][0]["opening"] = json!(1.0);
        }));
        v.push(m(&format!("trajectory {t}: a key pose moved 2 cm"), move |p| {
            add(&mut p["trajectories"][t]["key_poses"][0]["position"][2], 0.02)
        }));
    }
    v.push(m("a trajectory credited to another action", |p| {
        p["trajectories"][0]["action"] = json!(1)
    }));
    v.push(m("the robot's velocity limits raised", |p| {
        p["robot"]["velocity_limits"] = json!(vec![10.0; 6]);
    }));
    v.push(m("the robot's acceleration limit halved", |p| {
        let a = p["robot"]["timing"]["acceleration"].as_f64().unwrap();
        p["robot"]["timing"]["acceleration"] = json!(0.5 * a);
    }));
    // A plan that claims a faster cell than its instance allows, consistently, so that its own
    // trajectories pass its own limits: only the instance can refute it.
    v.push(m("the robot's speed scale raised to 1 with its velocity limits", |p| {
        p["robot"]["timing"]["velocity_scale"] = json!(1.0);
        p["robot"]["velocity_limits"] = json!(vec![0.5; 6]);
        p["options"]["trajectory"]["velocity_scale"] = json!(1.0);
    }));
    v.push(m("the robot's acceleration limit doubled, in the options too", |p| {
        let a = p["robot"]["timing"]["acceleration"].as_f64().unwrap();
        p["robot"]["timing"]["acceleration"] = json!(2.0 * a);
        p["options"]["trajectory"]["acceleration"] = json!(2.0 * a);
    }));
    v.push(m("the robot's execution time understated", |p| {
        add(&mut p["robot"]["execution_time_s"], -10.0)
    }));
    v
}

#[test]
fn the_untampered_plan_is_accepted() {
    assert_eq!(rejection(valid_plan()), None);
}

#[test]
fn every_tampered_plan_is_rejected() {
    let plan = valid_plan();
    let all = mutations(plan);
    assert!(all.len() >= 60, "{} mutations", all.len());
    let mut survivors = Vec::new();
    for (name, f) in &all {
        let mut p = plan.clone();
        f(&mut p);
        assert_ne!(&p, plan, "{name}: the mutation changed nothing");
        if rejection(&p).is_none() {
            survivors.push(name.clone());
        }
    }
    assert!(
        survivors.is_empty(),
        "{} of {} tampered plans pass the verifier:\n{}",
        survivors.len(),
        all.len(),
        survivors.join("\n")
    );
}

/// `pushpack export` refuses a plan whose trajectories a controller could not take, whatever
/// the instance: never a partial export.
#[test]
fn export_refuses_tampered_trajectories() {
    let plan = valid_plan();
    let dir = tempfile::tempdir().unwrap();
    let fmt = pushpack::plan::export::ExportFormat::RosJson;
    let p = Plan::from_json(&plan.to_string(), "plan.json").unwrap();
    pushpack::plan::export::export(&p, fmt, dir.path()).expect("the valid plan exports");
    let kinds = [
        "velocities of 1000 rad/s",
        "5 values for 6 joints",
        "time going backwards",
        "t = 1e300",
        "10× faster",
    ];
    let mut checked = 0;
    for (name, f) in mutations(plan)
        .iter()
        .filter(|(n, _)| kinds.iter().any(|k| n.contains(k)))
    {
        let mut v = plan.clone();
        f(&mut v);
        let Ok(p) = Plan::from_json(&v.to_string(), "tampered.json") else {
            checked += 1;
            continue;
        };
        let r = pushpack::plan::export::export(&p, fmt, dir.path());
        assert!(r.is_err(), "{name}: exported");
        checked += 1;
    }
    assert_eq!(checked, 3 * kinds.len());
}
