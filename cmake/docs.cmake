# The Markdown files (README.md, CONTRIBUTING.md, CHANGELOG.md, docs/*.md) render as written:
# test/docs/markdown_test.py renders each with cmark (Debian package cmark) and checks fences,
# headings and relative links. Run by `make test`; catkin_test_results sees its xunit result.
if(CATKIN_ENABLE_TESTING)
  catkin_add_nosetests(test/docs/markdown_test.py)
  # demo.launch's arguments against the node's parameters; make run's launch per scene.
  catkin_add_nosetests(test/launch/launch_args_test.py)
endif()
