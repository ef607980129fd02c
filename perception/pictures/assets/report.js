// report.html's behaviour (perception/pictures/report.py inlines it).
(function () {
  // Frame strips: the slider picks a frame; the label shows the time that frame shows.
  document.querySelectorAll('.strip').forEach(function (strip) {
    var frames = strip.querySelectorAll('img.frame');
    var view = strip.querySelector('img.view');
    var slider = strip.querySelector('input.slider');
    var label = strip.querySelector('.time');
    function show(i) {
      if (!frames.length) { return; }
      view.src = frames[i].src;
      label.textContent = frames[i].getAttribute('data-label');
      strip.setAttribute('data-index', String(i));
    }
    slider.addEventListener('input', function () { show(+slider.value); });
    show(0);
  });
  // Zoom controls: scale the picture in the box the control names; "fit" returns to 1.
  document.querySelectorAll('.zoom').forEach(function (control) {
    var box = document.getElementById(control.getAttribute('data-for'));
    var level = control.querySelector('.level');
    var zoom = 1;
    control.querySelectorAll('button').forEach(function (button) {
      button.addEventListener('click', function () {
        var step = button.getAttribute('data-step');
        zoom = step === 'fit' ? 1 : Math.min(8, Math.max(0.25, zoom * parseFloat(step)));
        box.style.setProperty('--zoom', String(zoom));
        level.textContent = Math.round(zoom * 100) + '%';
      });
    });
  });
  // Timeline: the operation under the pointer, in words.
  var info = document.getElementById('op-info');
  document.querySelectorAll('#timeline .op').forEach(function (bar) {
    bar.addEventListener('mouseenter', function () {
      info.textContent = bar.getAttribute('data-info');
    });
  });
  document.body.setAttribute('data-ready', 'yes');
})();
