// The 3D view of report.html (report/model_view_3d.h): draws the data of #pgba-view3d-data
// into #pgba-view3d with three.js (the global THREE, and THREE.OrbitControls): the cameras as
// frusta (lines from the centre to the image's corners, the image's rectangle and a
// translucent face), the points as dots. It draws once and again only when the view moves.
(function () {
  'use strict';
  var box = document.getElementById('pgba-view3d');
  var source = document.getElementById('pgba-view3d-data');
  if (!box || !source) return;

  function say(text) {
    var p = document.createElement('p');
    p.style.margin = '1em';
    p.textContent = text;
    box.appendChild(p);
  }

  // WebGL first: three.js reports a missing context on the console, the page says it in words.
  var probe = document.createElement('canvas');
  if (!window.WebGLRenderingContext || !(probe.getContext('webgl') || probe.getContext('experimental-webgl'))) {
    say('This browser cannot show the 3D view: WebGL is not available.');
    return;
  }

  try {
    draw(JSON.parse(source.textContent));
  } catch (e) {
    say('The 3D view failed: ' + e.message);
    console.error('pgba 3D view: ' + (e.stack || e));
  }

  function draw(data) {
    var cams = data.cameras, ncam = cams.length, cu = data.camera_unit;
    var background = new THREE.Color(0xeef1f5);

    // Frusta: 8 segments (16 vertices) and 2 triangles (6 vertices) per camera.
    var linePos = new Float32Array(ncam * 16 * 3), lineCol = new Float32Array(ncam * 16 * 3);
    var facePos = new Float32Array(ncam * 6 * 3), faceCol = new Float32Array(ncam * 6 * 3);
    var segments = [[0, 1], [0, 2], [0, 3], [0, 4], [1, 2], [2, 3], [3, 4], [4, 1]];
    var triangles = [1, 2, 3, 1, 3, 4];
    for (var i = 0; i < ncam; ++i) {
      var f = cams[i].frustum;
      for (var s = 0; s < 16; ++s) {
        var v = segments[s >> 1][s & 1];
        for (var a = 0; a < 3; ++a) linePos[(i * 16 + s) * 3 + a] = f[v * 3 + a] * cu;
      }
      for (var t = 0; t < 6; ++t)
        for (var b = 0; b < 3; ++b) facePos[(i * 6 + t) * 3 + b] = f[triangles[t] * 3 + b] * cu;
    }
    var lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', new THREE.BufferAttribute(linePos, 3));
    lineGeometry.setAttribute('color', new THREE.BufferAttribute(lineCol, 3));
    var faceGeometry = new THREE.BufferGeometry();
    faceGeometry.setAttribute('position', new THREE.BufferAttribute(facePos, 3));
    faceGeometry.setAttribute('color', new THREE.BufferAttribute(faceCol, 3));
    var faces = new THREE.Mesh(faceGeometry, new THREE.MeshBasicMaterial({
      vertexColors: THREE.VertexColors, transparent: true, opacity: 0.3, side: THREE.DoubleSide, depthWrite: false}));
    var scene = new THREE.Scene();
    scene.background = background;
    scene.add(new THREE.LineSegments(lineGeometry, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors})));
    scene.add(faces);

    // Points: their own colours, else dark grey.
    var np = data.points.length / 3;
    if (np > 0) {
      var pointPos = new Float32Array(data.points.length);
      for (var k = 0; k < data.points.length; ++k) pointPos[k] = data.points[k] * data.point_unit;
      var pointGeometry = new THREE.BufferGeometry();
      pointGeometry.setAttribute('position', new THREE.BufferAttribute(pointPos, 3));
      var pointMaterial = new THREE.PointsMaterial({size: 2, sizeAttenuation: false, color: 0x555555});
      if (data.colours) {
        var pointCol = new Float32Array(np * 3);
        for (var q = 0; q < np * 3; ++q) pointCol[q] = parseInt(data.colours.substr(q * 2, 2), 16) / 255;
        pointGeometry.setAttribute('color', new THREE.BufferAttribute(pointCol, 3));
        pointMaterial = new THREE.PointsMaterial({size: 2, sizeAttenuation: false, vertexColors: THREE.VertexColors});
      }
      scene.add(new THREE.Points(pointGeometry, pointMaterial));
    }

    // Colours: by residual (a scale through data.residual_colours) or by model.
    var stops = data.residual_colours.map(function (c) { return new THREE.Color(c); });
    function residualColour(r) {
      if (r === null) return new THREE.Color(data.no_residual_colour);
      var x = Math.min(Math.max(r / data.residual_scale, 0), 1) * (stops.length - 1);
      var j = Math.min(Math.floor(x), stops.length - 2);
      return stops[j].clone().lerp(stops[j + 1], x - j);
    }
    function paint(mode) {
      for (var i = 0; i < ncam; ++i) {
        var c = mode === 'model' ? new THREE.Color(data.models[cams[i].model].colour) : residualColour(cams[i].residual);
        for (var s = 0; s < 16; ++s) lineCol.set([c.r, c.g, c.b], (i * 16 + s) * 3);
        for (var t = 0; t < 6; ++t) faceCol.set([c.r, c.g, c.b], (i * 6 + t) * 3);
      }
      lineGeometry.attributes.color.needsUpdate = true;
      faceGeometry.attributes.color.needsUpdate = true;
    }

    // The view: every model in sight (each of radius 1 about its offset), from above and aside.
    var first = data.models[0].offset, last = data.models[data.models.length - 1].offset;
    var target = new THREE.Vector3((first[0] + last[0]) / 2, (first[1] + last[1]) / 2, (first[2] + last[2]) / 2);
    var radius = 1 + Math.max(Math.abs(last[0] - first[0]), Math.abs(last[1] - first[1]), Math.abs(last[2] - first[2])) / 2;
    var camera = new THREE.PerspectiveCamera(40, 1, radius / 1000, radius * 1000);
    // Close enough for the model to fill the view: its radius is half its box's diagonal.
    var distance = 0.8 * radius / Math.sin(20 * Math.PI / 180);  // 20 degrees: half the field of view
    var elevation = 30 * Math.PI / 180, azimuth = 30 * Math.PI / 180;
    camera.position.set(target.x + distance * Math.cos(elevation) * Math.sin(azimuth),
                        target.y + distance * Math.sin(elevation),
                        target.z + distance * Math.cos(elevation) * Math.cos(azimuth));
    camera.lookAt(target);

    var renderer = new THREE.WebGLRenderer({antialias: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    box.appendChild(renderer.domElement);
    function render() { renderer.render(scene, camera); }
    function fit() {
      var w = Math.max(box.clientWidth, 1), h = Math.max(box.clientHeight, 1);
      renderer.setSize(w, h);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      render();
    }
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(target);
    controls.screenSpacePanning = true;
    controls.enableKeys = false;
    controls.update();
    controls.addEventListener('change', render);
    window.addEventListener('resize', fit);

    // The colour switch (several models) and its legends.
    var mode = data.models.length > 1 ? 'model' : 'residual';
    var legends = {residual: document.getElementById('pgba-view3d-legend-residual'),
                   model: document.getElementById('pgba-view3d-legend-model')};
    function setMode(m) {
      mode = m;
      paint(mode);
      for (var key in legends)
        if (legends[key]) legends[key].style.display = key === mode ? '' : 'none';
      render();
    }
    var radios = document.querySelectorAll('input[name="pgba-view3d-colour"]');
    for (var n = 0; n < radios.length; ++n)
      radios[n].addEventListener('change', function (e) { if (e.target.checked) setMode(e.target.value); });

    // Hovering a camera's face names its image.
    var tip = document.createElement('div');
    tip.style.cssText = 'position:absolute;display:none;pointer-events:none;background:#fff;border:1px solid #888;' +
                        'padding:2px 6px;font-size:13px;white-space:nowrap';
    box.appendChild(tip);
    var raycaster = new THREE.Raycaster(), mouse = new THREE.Vector2();
    renderer.domElement.addEventListener('mousemove', function (e) {
      if (e.buttons) { tip.style.display = 'none'; return; }
      var rect = renderer.domElement.getBoundingClientRect();
      mouse.set((e.clientX - rect.left) / rect.width * 2 - 1, -(e.clientY - rect.top) / rect.height * 2 + 1);
      raycaster.setFromCamera(mouse, camera);
      var hit = raycaster.intersectObject(faces)[0];
      if (!hit) { tip.style.display = 'none'; return; }
      var c = cams[Math.floor(hit.faceIndex / 2)];
      tip.textContent = c.name + ': ' + (c.residual === null ? 'no point' : 'median error ' + c.residual.toFixed(3) + ' px') +
                        (data.models.length > 1 ? ', model ' + c.model : '');
      tip.style.left = (e.clientX - rect.left + 12) + 'px';
      tip.style.top = (e.clientY - rect.top + 12) + 'px';
      tip.style.display = '';
    });
    renderer.domElement.addEventListener('mouseleave', function () { tip.style.display = 'none'; });

    paint(mode);
    fit();
  }
})();
