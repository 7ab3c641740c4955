# Field rendering (issue 3): scalar maps, streamlines, text, colour bars and multi-panel
# frames, golden images on EGL and OSMesa (skipped cleanly without a context).
grainflow_add_tests(grainflow_tests_fields field_render_test.cpp LIBS grainflow_render)
