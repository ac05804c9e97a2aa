"""launch/demo.launch against the node: every parameter cloth_sim_node reads
(src/node/options.cpp) is a launch argument of the same name, passed to the node, with the
node's own default (include/cloth_sim/node/options.h), plus `ns`; and `make run SCENE=...` runs
fold with its pin script and grasp_demo with its scripted gripper (scripts/run_demo.sh,
DRY_RUN=1). roslaunch silently ignored a parameter that was not an argument (issue 23)."""
import os
import re
import subprocess
import xml.etree.ElementTree as ET

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def read(path):
    with open(os.path.join(ROOT, path)) as f:
        return f.read()


def node_parameters():
    return re.findall(r'read\.get\("([a-z_]+)"', read("src/node/options.cpp"))


def option_defaults():
    """name -> default of NodeOptions' plain number, bool and string fields."""
    text = read("include/cloth_sim/node/options.h")
    found = re.findall(r'^\s*(?:double|int|bool|std::string)\s+([a-z_]+)\s*=\s*([^;]+);', text, re.M)
    return dict(found)


def launch():
    return ET.fromstring(read("launch/demo.launch"))


def test_every_node_parameter_is_an_argument_passed_to_the_node():
    root = launch()
    args = {a.get("name"): a.get("default") for a in root.iter("arg")}
    node = next(n for n in root.iter("node") if n.get("type") == "cloth_sim_node")
    params = {}
    for p in node.iter("param"):
        params.setdefault(p.get("name"), []).append(p.get("value") or p.get("textfile"))
    assert "ns" in args, "no ns argument"
    names = node_parameters()
    assert len(names) >= 25, names
    for name in names:
        assert name in args, "parameter ~%s is no argument of demo.launch" % name
        assert name in params, "argument %s is not passed to the node" % name
        assert any("$(arg %s)" % name in (v or "") for v in params[name]), (name, params[name])


def test_the_arguments_defaults_are_the_nodes():
    args = {a.get("name"): a.get("default") for a in launch().iter("arg")}
    defaults = option_defaults()
    checked = 0
    for name, value in defaults.items():
        if name not in args or name == "scene":
            continue
        value = value.strip().strip('"')
        launch_value = args[name]
        try:
            assert float(launch_value) == float(value), (name, launch_value, value)
        except ValueError:
            assert launch_value == value, (name, launch_value, value)
        checked += 1
    assert checked >= 15, checked


def run_demo(scene):
    env = dict(os.environ, SCENE=scene, DRY_RUN="1")
    env.pop("DISPLAY", None)
    out = subprocess.run(["bash", os.path.join(ROOT, "scripts", "run_demo.sh")], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    assert out.returncode == 0, out.stdout
    return out.stdout.strip().splitlines()[-1]


def test_make_run_runs_each_scene_with_its_script():
    assert "fold_demo.launch" in run_demo("fold")
    grasp = run_demo("grasp_demo")
    assert "grasp_demo.launch" in grasp and "loop:=" in grasp, grasp
    assert "pinch_demo.launch" in run_demo("pinch")
    assert "demo.launch scene:=hanging" in run_demo("hanging")
    fold_launch = ET.fromstring(read("launch/fold_demo.launch"))
    assert any(n.get("type") == "fold_pin.py" for n in fold_launch.iter("node"))
