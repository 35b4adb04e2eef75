"""freespace.Config from YAML text, YAML files and dicts, with the engine's messages."""

import os
import pickle
import unittest

import freespace as fs
from common import source_dir


class ConfigTest(unittest.TestCase):
    def test_defaults_round_trip_through_yaml(self):
        c = fs.Config()
        self.assertEqual(fs.Config.from_yaml(c.to_yaml()), c)
        d = c.to_dict()
        self.assertEqual(d["map"]["width_cells"], 300)
        self.assertEqual(d["sensor_model"]["p_free"], 0.40)
        self.assertIs(d["clutter"]["enabled"], True)
        self.assertEqual(d["backend"]["kind"], "tbb")

    def test_file_string_and_dict_agree(self):
        path = os.path.join(source_dir(), "configs", "scala.yaml")
        from_file = fs.Config.from_yaml_file(path)
        with open(path) as f:
            from_text = fs.Config.from_yaml(f.read())
        self.assertEqual(from_file, from_text)
        self.assertEqual(fs.Config.from_dict(from_file.to_dict()), from_file)
        self.assertEqual(from_file.to_dict()["sensor"]["mount_x_m"], 3.7)
        self.assertEqual(from_file.to_dict()["polygon"]["shape"], "inside")

    def test_dotted_and_nested_overrides(self):
        a = fs.Config.from_dict({"polygon.margin_cells": 1, "polygon.shape": "inside"})
        b = fs.Config().with_overrides({"polygon": {"margin_cells": 1, "shape": "inside"}})
        self.assertEqual(a, b)
        self.assertEqual(a.to_dict()["polygon"]["margin_cells"], 1)
        self.assertNotEqual(a, fs.Config())
        c = a.with_overrides({"polygon.epsilon_m": 0.125})
        self.assertEqual(c.to_dict()["polygon"]["epsilon_m"], 0.125)
        self.assertEqual(c.to_dict()["polygon"]["margin_cells"], 1)  # kept from a

    def test_validation_messages_are_the_engines(self):
        with self.assertRaises(fs.ConfigError) as from_yaml:
            fs.Config.from_yaml("polygon:\n  max_vertices: 2\n")
        with self.assertRaises(fs.ConfigError) as from_dict:
            fs.Config.from_dict({"polygon": {"max_vertices": 2}})
        self.assertIn("polygon.max_vertices = 2", str(from_yaml.exception))
        self.assertEqual(str(from_yaml.exception), str(from_dict.exception))
        self.assertIsInstance(from_dict.exception, ValueError)

    def test_unknown_fields_and_bad_values_name_the_field(self):
        with self.assertRaisesRegex(fs.ConfigError, r"dict: unknown field 'polygon\.foo'"):
            fs.Config.from_dict({"polygon.foo": 1})
        with self.assertRaisesRegex(fs.ConfigError, r"unknown section 'nothing'"):
            fs.Config.from_yaml("nothing:\n  x: 1\n")
        with self.assertRaisesRegex(fs.ConfigError, r"sensor_model\.kind"):
            fs.Config.from_dict({"sensor_model.kind": "magic"})
        with self.assertRaisesRegex(fs.ConfigError, r"yaml:\d+: not valid YAML"):
            fs.Config.from_yaml("map:\n  width_cells: [1\n")
        with self.assertRaisesRegex(fs.ConfigError, r"cannot open '/no/such/file.yaml'"):
            fs.Config.from_yaml_file("/no/such/file.yaml")
        with self.assertRaisesRegex(TypeError, r"polygon\.max_vertices.*bool, int, float or str"):
            fs.Config.from_dict({"polygon.max_vertices": [3]})
        with self.assertRaisesRegex(TypeError, r"section\.field"):
            fs.Config.from_dict({"polygon": 3})

    def test_to_dict_keeps_each_fields_type_and_a_rigs_list(self):
        c = fs.Config.from_dict({"backend": {"opencl_device": "007", "opencl_platform": "true"}})
        d = c.to_dict()
        self.assertEqual(d["backend"]["opencl_device"], "007")  # a str, not the int 7
        self.assertEqual(d["backend"]["opencl_platform"], "true")
        self.assertIsInstance(d["map"]["width_cells"], int)
        self.assertIsInstance(d["map"]["resolution_m"], float)
        self.assertIs(d["clutter"]["enabled"], True)
        self.assertEqual(fs.Config.from_dict(d), c)
        rig = fs.Config.from_yaml_file(os.path.join(source_dir(), "configs", "surround.yaml"))
        sensors = rig.to_dict()["sensors"]
        self.assertEqual([s["name"] for s in sensors],
                         ["front_left", "front_right", "rear_left", "rear_right"])
        self.assertEqual(sensors[0]["mount_x_m"], 3.7)
        self.assertEqual(fs.Config.from_dict(rig.to_dict()), rig)

    def test_a_field_given_twice_is_an_error(self):
        with self.assertRaisesRegex(fs.ConfigError, r"map\.width_cells is given twice"):
            fs.Config.from_dict({"map.width_cells": 100, "map": {"width_cells": 200}})

    def test_pickles(self):
        c = fs.Config.from_dict({"classify.vehicle_width_m": 0.4})
        self.assertEqual(pickle.loads(pickle.dumps(c)), c)


if __name__ == "__main__":
    unittest.main()
