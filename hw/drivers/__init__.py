"""pyserial drivers: one pure codec module (bytes <-> messages, no I/O) and one driver class per
device. Drivers open ``serial.serial_for_url(url)``, run a reader thread (or ``poll()`` in
lock-step), reconnect after an unplug or a silence, and stamp messages on the injected Clock.

=============  ===================  =====================  ==============================
device         codec                driver                 interface
=============  ===================  =====================  ==============================
URG-04LX       ``scip``             ``urg04lx.Urg04lxDriver``  Laser
LMS 200/291    ``lms2xx_codec``     ``lms2xx.Lms2xxDriver``    Laser
Kobuki         ``kobuki_codec``     ``kobuki.KobukiDriver``    Base (watchdog ``cmd_vel_timeout``)
Arduino base   ``arduino_codec``    ``arduino.ArduinoBaseDriver``  Base (``base_controller_timeout``)
Razor AHRS     ``razor_codec``      ``razor.RazorDriver``      ImuSensor
VectorNav      ``vectornav_codec``  ``vectornav.VectorNavDriver``  ImuSensor
=============  ===================  =====================  ==============================

``serial_link`` holds what all drivers share; ``hw.devices.open_devices`` builds them from URLs.
"""
